// lathectl — command-line front end: run scenarios, validate them, run the demo, and the papers'
// design calculators. Exit codes: 0 success, 1 internal failure, 2 bad input (one clear message),
// 3 `--strict` and a claim not met, an alarm raised or a part not finished.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "lathectl/design/adaptive_speed.hpp"
#include "lathectl/design/pulse_regulator.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/hydraulics/tracer.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/install_paths.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl_version.hpp"

namespace fs = std::filesystem;
using namespace lathectl;

namespace {

// The example scenarios: the installed ones for an installed program, the source tree's for a
// build-tree program, $LATHECTL_EXAMPLES_DIR over both.
std::string examples_dir() {
  return io::locate_tree(
      "LATHECTL_EXAMPLES_DIR",
      {LATHECTL_EXAMPLES_DIR, LATHECTL_EXAMPLES_SUBDIR, LATHECTL_INSTALLED_EXAMPLES_DIR}, "");
}

// The description's first sentence, or its first words up to about 140 characters.
std::string first_sentence(const std::string& d) {
  const auto dot = d.find(". ");
  if (dot != std::string::npos && dot < 180) return d.substr(0, dot + 1);
  if (d.size() <= 160) return d;
  const auto cut = d.rfind(' ', 140);
  return d.substr(0, cut == std::string::npos ? 140 : cut) + " …";
}

constexpr int kStrictFailure = 3;  // --strict: a claim not met, an alarm or an unfinished part

// The demo index's entry for a run: ✔/✘ and a link to each unmet claim in its report.
io::IndexEntry index_entry(const io::Scenario& sc, const io::RunOutput& r) {
  io::IndexEntry e;
  e.title = sc.name + " — " + first_sentence(sc.description);
  e.href = sc.name + "/report.html";
  e.summary = r.headline;
  e.status = r.verdict.ok() ? 1 : -1;
  e.verdict = r.verdict.line(false);
  for (const auto& u : r.verdict.unmet)
    e.problems.push_back({"✘ " + u.text, e.href + "#claim-" + std::to_string(u.index)});
  for (const auto& a : r.verdict.alarms) e.problems.push_back({"alarm: " + a, e.href + "#verdict"});
  for (const auto& l : r.verdict.unfinished)
    e.problems.push_back({"part not finished: " + l, e.href + "#verdict"});
  return e;
}

int cmd_run(const std::string& scenario, const std::string& out, bool strict) {
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = io::load_scenario(scenario, lib);
  io::prepare_output_dir(out, "--out");  // before the simulation, not after it
  io::RunOutput result;
  {
    io::Progress progress("run " + sc.name);
    io::ProgressScope scope(progress);
    result = io::run_scenario(sc);
  }
  try {
    io::write_outputs(result, out);
  } catch (const std::filesystem::filesystem_error& e) {
    throw io::InputError("--out " + out + ": cannot write the results there (" +
                         e.code().message() + ")");
  }
  std::cout << sc.name << ": " << result.headline << " — " << result.verdict.line() << "\n  → "
            << (fs::path(out) / "report.html").string() << "\n";
  return strict && !result.verdict.ok() ? kStrictFailure : 0;
}

int cmd_check(const std::string& scenario) {
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = io::load_scenario(scenario, lib);
  std::cout << scenario << ": OK (system " << sc.system << ", \"" << sc.name << "\", "
            << sc.run.duration_s << " s at step " << sc.run.step_s << " s)\n";
  return 0;
}

int cmd_demo(const std::string& out, const std::string& dir, const std::vector<std::string>& only,
             bool strict) {
  const auto lib = io::MaterialLibrary::load_default();
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw io::InputError("--examples " + dir + ": not a directory");
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".toml") files.push_back(it->path());
  if (ec) throw io::InputError("--examples " + dir + ": " + ec.message());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw io::InputError(dir + ": no example scenarios (*.toml) found");
  if (!only.empty()) {
    std::vector<fs::path> chosen;
    for (const auto& name : only) {
      const auto it = std::find_if(files.begin(), files.end(),
                                   [&](const fs::path& f) { return f.stem() == name; });
      if (it == files.end()) {
        std::string known;
        for (const auto& f : files) known += (known.empty() ? "" : ", ") + f.stem().string();
        throw io::InputError("demo: no example '" + name + "' in " + dir + " (known: " + known +
                             ")");
      }
      if (std::find(chosen.begin(), chosen.end(), *it) == chosen.end()) chosen.push_back(*it);
    }
    files = std::move(chosen);
  }
  // Parse all first: nothing runs on a half-read example set.
  std::vector<io::Scenario> scenarios;
  for (const auto& f : files) scenarios.push_back(io::load_scenario(f.string(), lib));
  io::prepare_output_dir(out, "--out", false);

  std::vector<io::IndexEntry> entries(scenarios.size());
  std::vector<std::string> errors(scenarios.size());
  std::vector<char> failed(scenarios.size(), 0);
  std::atomic<std::size_t> next{0}, done{0};
  io::Progress progress("demo");
  auto worker = [&] {
    for (std::size_t i; (i = next++) < scenarios.size();) {
      try {
        const auto r = io::run_scenario(scenarios[i]);
        const fs::path sub = fs::path(out) / scenarios[i].name;
        io::write_outputs(r, sub);
        entries[i] = index_entry(scenarios[i], r);
        failed[i] = r.verdict.ok() ? 0 : 1;
        progress.print_above([&] {
          std::cout << "  " << scenarios[i].name << ": " << r.headline << " — "
                    << r.verdict.line() << std::endl;
        });
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
      const std::size_t k = ++done;
      progress.update(static_cast<double>(k) / static_cast<double>(scenarios.size()),
                      std::to_string(k) + " of " + std::to_string(scenarios.size()) +
                          " scenarios");
    }
  };
  const unsigned n = std::max(1u, std::min(std::thread::hardware_concurrency(), 8u));
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < n; ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  progress.finish();
  for (const auto& e : errors)
    if (!e.empty()) throw std::runtime_error(e);
  io::write_file_atomic(fs::path(out) / "index.html",
                        io::render_index_html("lathectl demo — example scenarios", entries));
  std::string which;
  std::size_t n_failed = 0;
  for (std::size_t i = 0; i < scenarios.size(); ++i)
    if (failed[i]) which += (n_failed++ ? ", " : "") + scenarios[i].name;
  std::cout << "demo: " << scenarios.size() << " scenarios, " << n_failed
            << " with unmet claims, alarms or unfinished parts" << (n_failed ? " (" + which + ")" : "")
            << " → " << (fs::path(out) / "index.html").string() << "\n";
  return strict && n_failed > 0 ? kStrictFailure : 0;
}

void print_value(bool json_first, const char* key, double si, const char* si_unit, double shop,
                 const char* shop_unit, bool last = false) {
  (void)json_first;
  std::printf("  %-34s %14.6g %-10s %14.6g %s%s", key, si, si_unit, shop, shop_unit,
              last ? "\n" : "\n");
}

// `design adaptive-speed`: seed 004's V_opt and the handbook tool-life law, shop units.
struct AdaptiveSpeedArgs {
  std::optional<double> Vp, Sp, yv, S;  // V_opt group [m/min, mm/rev, -, mm/rev]
  // Tool-life groups: Cv, m, xv [-], t [mm], s [mm/rev], V [m/min], T [min].
  std::optional<double> Cv, m, xv, t, s, V, T;
  std::optional<double> F, n;  // feed per revolution group [mm/min, rpm]
  std::string material;
  bool json = false;
};

// Extended-Taylor coefficients for one calculation: explicit options win; the rest come from the
// material's tool-life range that contains the calculation's feed (as CuttingModel chooses it).
struct TaylorCoefficients {
  std::optional<double> Cv, m, xv, yv;
  const cutting::ToolLifeRange* range = nullptr;  // the material range used, if any
};

const cutting::ToolLifeRange& life_range(const cutting::Material& mat, double feed_mm_per_rev) {
  const auto n = static_cast<std::size_t>(mat.tool_life_ranges);
  for (std::size_t i = 0; i < n; ++i)
    if (feed_mm_per_rev <= mat.tool_life[i].feed_max_mm_per_rev) return mat.tool_life[i];
  return mat.tool_life[n - 1];
}

TaylorCoefficients coefficients(const AdaptiveSpeedArgs& a, const cutting::Material* mat,
                                std::optional<double> feed) {
  TaylorCoefficients c{a.Cv, a.m, a.xv, a.yv, nullptr};
  if (mat && feed) {
    const auto& r = life_range(*mat, *feed);
    const bool used = !c.Cv || !c.m || !c.xv || !c.yv;
    if (!c.Cv) c.Cv = r.Cv;
    if (!c.m) c.m = r.m;
    if (!c.xv) c.xv = r.xv;
    if (!c.yv) c.yv = r.yv;
    if (used) c.range = &r;
  }
  return c;
}

// The options of a group that are still missing ("--yv", ...).
std::string missing(std::initializer_list<std::pair<const std::optional<double>*, const char*>> l) {
  std::string out;
  for (const auto& [v, name] : l)
    if (!v->has_value()) out += (out.empty() ? "" : " ") + std::string(name);
  return out;
}

int cmd_adaptive_speed(const AdaptiveSpeedArgs& a) {
  const std::string who = "design adaptive-speed: ";
  io::MaterialLibrary lib;
  const cutting::Material* mat = nullptr;
  if (!a.material.empty()) {
    lib = io::MaterialLibrary::load_default();
    mat = lib.find(a.material);
    if (!mat) {
      std::string known;
      for (const auto& nm : lib.names()) known += (known.empty() ? "" : ", ") + nm;
      throw io::InputError(who + "unknown material '" + a.material + "' (known: " + known + ")");
    }
    if (mat->tool_life_ranges == 0)
      throw io::InputError(who + "material '" + a.material + "' has no tool-life data");
  }
  const auto c_opt = coefficients(a, mat, a.S);  // V_opt: the range of the current feed
  const auto c_life = coefficients(a, mat, a.s);
  const char* yv_hint = mat ? "--yv" : "--yv (or --material)";
  const std::string miss_opt =
      missing({{&a.Vp, "--Vp"}, {&a.Sp, "--Sp"}, {&c_opt.yv, yv_hint}, {&a.S, "--S"}});
  const std::string miss_taylor = missing({{&c_life.Cv, "--Cv"},
                                           {&c_life.m, "--m"},
                                           {&c_life.xv, "--xv"},
                                           {&c_life.yv, "--yv"},
                                           {&a.t, "--t"},
                                           {&a.s, "--s"}});
  const std::string miss_life = missing({{&a.V, "--V"}});
  const std::string miss_speed = missing({{&a.T, "--T-target"}});
  const std::string miss_feed = missing({{&a.F, "--F"}, {&a.n, "--n"}});
  const bool do_opt = miss_opt.empty();
  const bool do_life = miss_taylor.empty() && miss_life.empty();
  const bool do_speed = miss_taylor.empty() && miss_speed.empty();
  const bool do_feed = miss_feed.empty();
  if (!do_opt && !do_life && !do_speed && !do_feed)
    throw io::InputError(
        who +
        "nothing to compute; give a complete group: --Vp --Sp --yv --S (optimal speed "
        "V_opt); --Cv --m --xv --yv --t --s --V (tool life T); --Cv --m --xv --yv --t --s "
        "--T-target (speed for a target life); --F --n (feed per revolution); --material "
        "NAME supplies --Cv --m --xv --yv");
  // A group begun but not finished is skipped, and said so (on stderr: stdout stays JSON).
  const bool taylor_begun = a.Cv || a.m || a.xv || a.t || a.s || a.V || a.T;
  if (!do_opt && (a.Vp || a.Sp || a.S))
    std::cerr << "note: V_opt not computed, missing " << miss_opt << "\n";
  if (a.V && !do_life) std::cerr << "note: tool life not computed, missing " << miss_taylor << "\n";
  if (a.T && !do_speed)
    std::cerr << "note: speed for life not computed, missing " << miss_taylor << "\n";
  if (taylor_begun && !a.V && !a.T)
    std::cerr << "note: tool-life inputs given without --V or --T-target\n";
  if (!do_feed && (a.F || a.n))
    std::cerr << "note: feed per revolution not computed, missing " << miss_feed << "\n";

  double v_opt = 0, life = 0, v_life = 0, feed = 0;
  try {
    if (do_opt) v_opt = design::optimal_speed(*a.Vp, *a.Sp, *c_opt.yv, *a.S);
    if (do_life)
      life = design::tool_life_min(*c_life.Cv, *c_life.m, *c_life.xv, *c_life.yv, *a.V, *a.t, *a.s);
    if (do_speed)
      v_life =
          design::speed_for_life(*c_life.Cv, *c_life.m, *c_life.xv, *c_life.yv, *a.T, *a.t, *a.s);
    if (do_feed) feed = design::feed_per_rev(*a.F, *a.n);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(who + e.what());
  }

  if (a.json) {
    nlohmann::json in = nlohmann::json::object();
    const std::pair<const std::optional<double>*, const char*> keys[] = {
        {&a.Vp, "Vp_m_per_min"}, {&a.Sp, "Sp_mm_per_rev"},
        {&a.yv, "yv"},           {&a.S, "S_mm_per_rev"},
        {&a.Cv, "Cv"},           {&a.m, "m"},
        {&a.xv, "xv"},           {&a.t, "t_mm"},
        {&a.s, "s_mm_per_rev"},  {&a.V, "V_m_per_min"},
        {&a.T, "T_target_min"},  {&a.F, "F_mm_per_min"},
        {&a.n, "n_rpm"}};
    for (const auto& [v, k] : keys)
      if (*v) in[k] = **v;
    if (mat) in["material"] = mat->name;
    auto coeffs = [&](const TaylorCoefficients& c, bool all) {
      nlohmann::json j;
      if (all)
        j = {{"Cv", *c.Cv}, {"m", *c.m}, {"xv", *c.xv}, {"yv", *c.yv}};
      else
        j = {{"yv", *c.yv}};
      if (c.range) {
        j["material"] = mat->name;
        j["range_feed_max_mm_per_rev"] = c.range->feed_max_mm_per_rev;
      }
      return j;
    };
    nlohmann::json res = nlohmann::json::object(), used = nlohmann::json::object();
    if (do_opt) {
      res["V_opt_m_per_min"] = v_opt;
      used["V_opt"] = coeffs(c_opt, false);
    }
    if (do_life) res["tool_life_min"] = life;
    if (do_speed) res["speed_for_life_m_per_min"] = v_life;
    if (do_life || do_speed) used["tool_life"] = coeffs(c_life, true);
    if (do_feed) res["feed_per_rev_mm_per_rev"] = feed;
    nlohmann::json j;
    j["inputs"] = in;
    j["coefficients"] = used;
    j["results"] = res;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  auto row = [](const char* what, double v, const char* unit) {
    std::printf("  %-46s %14.6g %s\n", what, v, unit);
  };
  auto source = [&](const TaylorCoefficients& c) {
    if (!c.range) return std::string("options");
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s, feed range <= %g mm/rev", mat->name.c_str(),
                  c.range->feed_max_mm_per_rev);
    return std::string(buf);
  };
  std::printf("Adaptive cutting speed (seed 004) and tool life (extended Taylor, handbook)\n");
  if (do_opt) {
    std::printf("  V_opt = V_p·(S_p/S)^yv with yv = %g (%s)\n", *c_opt.yv,
                a.yv ? "options" : source(c_opt).c_str());
    row("optimal cutting speed V_opt", v_opt, "m/min");
  }
  if (do_life || do_speed)
    std::printf("  V = Cv/(T^m·t^xv·s^yv) with Cv = %g, m = %g, xv = %g, yv = %g (%s)\n",
                *c_life.Cv, *c_life.m, *c_life.xv, *c_life.yv, source(c_life).c_str());
  if (do_life) row("tool life T at V", life, "min");
  if (do_speed) row("speed V_T for the target life", v_life, "m/min");
  if (do_feed) row("feed per revolution s = F/n", feed, "mm/rev");
  return 0;
}

// `design gauge`: seed 003's linearised vibro-contact gauging, (20)-(25), options in shop units.
struct GaugeArgs {
  double supply_V = 24.0, supply_Hz = 50.0, coil_turns = 1000.0, coil_ohm = 50.0, coil_H = 0.5;
  double force_coeff = 2.11e8;  // N/Wb²
  double probe_mass_g = 20.0;
  double probe_damping = 1.382;  // N·s/m
  double probe_stiffness_N_per_mm = 9.554;
  double generator = 50.0;  // V per m/s
  double generator_ms = 0.2, filter_ms = 100.0, relay_ms = 20.0;
  double allowance_um = 250.0;         // m_x
  double removal_um_per_s = 20.0;      // a
  double target_um = 100.0;            // x_k
  double noise_sigma_um = 2.0;         // sqrt(D)
  double noise_beta = 5.0;             // β [1/s]
  std::optional<double> tolerance_um;  // ± tolerance → Cp
  bool json = false;
};

int cmd_gauge(const GaugeArgs& a) {
  const std::string who = "design gauge: ";
  design::GaugeInput in;
  in.supply_V = a.supply_V;
  in.supply_Hz = a.supply_Hz;
  in.coil_turns = a.coil_turns;
  in.coil_resistance_ohm = a.coil_ohm;
  in.coil_inductance_H = a.coil_H;
  in.force_coefficient_N_per_Wb2 = a.force_coeff;
  in.probe_mass_kg = a.probe_mass_g * 1e-3;
  in.probe_damping_N_s_per_m = a.probe_damping;
  in.probe_stiffness_N_per_m = a.probe_stiffness_N_per_mm * 1e3;
  in.generator_V_per_m_per_s = a.generator;
  in.generator_time_constant_s = a.generator_ms * 1e-3;
  in.filter_time_constant_s = a.filter_ms * 1e-3;
  in.relay_response_s = a.relay_ms * 1e-3;
  in.allowance_m = a.allowance_um * 1e-6;
  in.removal_m_per_s = a.removal_um_per_s * 1e-6;
  in.target_m = a.target_um * 1e-6;
  in.noise_variance_m2 = a.noise_sigma_um * a.noise_sigma_um * 1e-12;
  in.noise_beta_per_s = a.noise_beta;
  if (!(a.target_um < a.allowance_um)) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "--target-um (%g) must be below --allowance-um (%g): nothing to remove",
                  a.target_um, a.allowance_um);
    throw io::InputError(who + buf);
  }
  design::GaugeResult r;
  try {
    r = design::gauge(in);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(who + e.what());
  }
  if (!(r.threshold_V > 0.0)) {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        "no usable threshold: S_th = %.4g V <= 0, since x_k + a·(T_f + t_r) = %.4g µm "
        "reaches the free amplitude A0 = %.4g µm",
        r.threshold_V,
        (in.target_m + in.removal_m_per_s * (in.filter_time_constant_s + in.relay_response_s)) *
            1e6,
        r.free_amplitude_m * 1e6);
    throw io::InputError(who + buf);
  }
  if (in.allowance_m > r.free_amplitude_m)
    std::cerr << "note: allowance " << a.allowance_um
              << " µm exceeds the largest measurable A0 = " << r.free_amplitude_m * 1e6
              << " µm; the gauge reads nothing until x < A0\n";
  const double sigma_y = std::sqrt(r.noise_variance_V2);
  const bool has_tol = a.tolerance_um.has_value();
  const double tol_m = has_tol ? *a.tolerance_um * 1e-6 : 0.0;
  const double cp = has_tol ? (r.size_sigma_m > 0.0 ? 2.0 * tol_m / (6.0 * r.size_sigma_m)
                                                    : std::numeric_limits<double>::infinity())
                            : 0.0;
  if (a.json) {
    nlohmann::json j;
    j["inputs"] = {{"supply_V", a.supply_V},
                   {"supply_Hz", a.supply_Hz},
                   {"coil_turns", a.coil_turns},
                   {"coil_ohm", a.coil_ohm},
                   {"coil_H", a.coil_H},
                   {"force_coeff_N_per_Wb2", a.force_coeff},
                   {"probe_mass_g", a.probe_mass_g},
                   {"probe_damping_N_s_per_m", a.probe_damping},
                   {"probe_stiffness_N_per_mm", a.probe_stiffness_N_per_mm},
                   {"generator_V_per_m_per_s", a.generator},
                   {"generator_ms", a.generator_ms},
                   {"filter_ms", a.filter_ms},
                   {"relay_ms", a.relay_ms},
                   {"allowance_um", a.allowance_um},
                   {"removal_um_per_s", a.removal_um_per_s},
                   {"target_um", a.target_um},
                   {"noise_sigma_um", a.noise_sigma_um},
                   {"noise_beta_per_s", a.noise_beta}};
    if (has_tol) j["inputs"]["tolerance_um"] = *a.tolerance_um;
    j["si"] = {{"A0_m", r.free_amplitude_m},
               {"static_offset_m", r.static_offset_m},
               {"K_V_per_m", r.signal_gain_V_per_m},
               {"intercept_m", r.intercept_m},
               {"S_target_V", r.signal_at_target_V},
               {"S_th_V", r.threshold_V},
               {"t_k_s", r.end_time_s},
               {"D_y_V2", r.noise_variance_V2},
               {"sigma_y_V", sigma_y},
               {"sigma_x_m", r.size_sigma_m}};
    j["shop"] = {{"A0_um", r.free_amplitude_m * 1e6},
                 {"static_offset_um", r.static_offset_m * 1e6},
                 {"K_mV_per_um", r.signal_gain_V_per_m * 1e-3},
                 {"intercept_um", r.intercept_m * 1e6},
                 {"S_target_V", r.signal_at_target_V},
                 {"S_th_V", r.threshold_V},
                 {"t_k_s", r.end_time_s},
                 {"D_y_V2", r.noise_variance_V2},
                 {"sigma_y_mV", sigma_y * 1e3},
                 {"sigma_x_um", r.size_sigma_m * 1e6}};
    if (has_tol) {
      // Cp is unbounded without noise: JSON has no infinity, so null.
      const nlohmann::json cpj = std::isfinite(cp) ? nlohmann::json(cp) : nlohmann::json(nullptr);
      j["si"]["Cp"] = cpj;
      j["shop"]["Cp"] = cpj;
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf(
      "Vibro-contact in-process gauge (seed 003, linearised (20)-(25))\n  %-34s %14s %-10s %14s "
      "%s\n",
      "", "SI", "", "shop", "");
  print_value(false, "free amplitude A0 (max allowance)", r.free_amplitude_m, "m",
              r.free_amplitude_m * 1e6, "µm");
  print_value(false, "static probe offset", r.static_offset_m, "m", r.static_offset_m * 1e6, "µm");
  print_value(false, "signal gain K", r.signal_gain_V_per_m, "V/m", r.signal_gain_V_per_m * 1e-3,
              "mV/µm");
  print_value(false, "intercept B0/q1 (20)", r.intercept_m, "m", r.intercept_m * 1e6, "µm");
  print_value(false, "signal at target K·(A0 − x_k)", r.signal_at_target_V, "V",
              r.signal_at_target_V, "V");
  print_value(false, "threshold S_th (23)", r.threshold_V, "V", r.threshold_V, "V");
  print_value(false, "end of cut t_k (22)", r.end_time_s, "s", r.end_time_s, "s");
  print_value(false, "signal noise D_y (25)", r.noise_variance_V2, "V²", r.noise_variance_V2, "V²");
  print_value(false, "signal noise σ_y = sqrt(D_y)", sigma_y, "V", sigma_y * 1e3, "mV");
  print_value(false, "size scatter σ_x", r.size_sigma_m, "m", r.size_sigma_m * 1e6, "µm");
  if (has_tol) print_value(false, "Cp = 2·tol/(6·σ_x)", cp, "", cp, "");
  return 0;
}

// `design tracer`: seed 002's linearised one-coordinate hydraulic tracer slide, shop units.
struct TracerArgs {
  double E0_N_per_mm = 2000.0;   // stiffness ∂P/∂h per mm of spool opening
  double C0_per_s = 20.0;        // velocity gain ∂V/∂h
  double mass_kg = 100.0;        // M
  double lever = 3.0;            // i
  double P0_N = 500.0;           // cutting + dry friction
  double beta_deg = 45.0;        // guide inclination β
  double alpha_deg = 30.0;       // cone angle α
  double feed_mm_per_rev = 0.3;  // s
  double rpm = 600.0;            // n
  bool json = false;
};

int cmd_tracer(const TracerArgs& a) {
  const std::string who = "design tracer: ";
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  char buf[200];
  if (!(a.beta_deg > 0.0 && a.beta_deg <= 90.0)) {
    std::snprintf(buf, sizeof buf, "--beta-deg must be in (0, 90], got %g", a.beta_deg);
    throw io::InputError(who + buf);
  }
  if (!(a.alpha_deg <= 90.0)) {
    std::snprintf(buf, sizeof buf, "--alpha-deg must be <= 90 (a template y(x)), got %g",
                  a.alpha_deg);
    throw io::InputError(who + buf);
  }
  if (!(a.alpha_deg + a.beta_deg < 180.0) || !(a.alpha_deg > -a.beta_deg)) {
    std::snprintf(buf, sizeof buf,
                  "the slide cannot follow this cone: need -β < α < 180° - β, got α = %g°, "
                  "β = %g°",
                  a.alpha_deg, a.beta_deg);
    throw io::InputError(who + buf);
  }
  hydraulics::TracerLinear t;
  t.E0_N_per_m = a.E0_N_per_mm * 1e3;
  t.C0_per_s = a.C0_per_s;
  t.mass_kg = a.mass_kg;
  t.lever_ratio = a.lever;
  t.P0_N = a.P0_N;
  const double al = a.alpha_deg * kDeg, be = a.beta_deg * kDeg;
  const double v_pr = a.feed_mm_per_rev * a.rpm / 60.0 * 1e-3;  // m/s
  const double v_t = v_pr * std::sin(al) / std::sin(al + be);   // m/s along the slide
  const double q_ss = t.steady_lag_m(v_t);                      // m along the slide
  const double q_static = t.static_offset_m();
  const double q_dyn = q_ss - q_static;  // v_T/(C0·i)
  const double zeta = t.zeta(), wn = t.omega_n(), fn = wn / (2.0 * 3.14159265358979323846);
  const auto tr = t.transient(0.0, v_t, v_t);
  if (!std::isfinite(q_ss) || !std::isfinite(tr.peak_m) || !std::isfinite(tr.settling_s))
    throw io::InputError(who + "the inputs give no finite result");
  if (a.json) {
    nlohmann::json j;
    j["inputs"] = {{"E0_N_per_mm", a.E0_N_per_mm},
                   {"C0_per_s", a.C0_per_s},
                   {"M_kg", a.mass_kg},
                   {"i", a.lever},
                   {"P0_N", a.P0_N},
                   {"beta_deg", a.beta_deg},
                   {"alpha_deg", a.alpha_deg},
                   {"s_mm_per_rev", a.feed_mm_per_rev},
                   {"n_rpm", a.rpm}};
    j["si"] = {{"V_pr_m_per_s", v_pr},
               {"v_T_m_per_s", v_t},
               {"q_ss_m", q_ss},
               {"q_ss_axial_m", q_ss * std::cos(be)},
               {"q_ss_radial_m", q_ss * std::sin(be)},
               {"q_static_m", q_static},
               {"q_dynamic_m", q_dyn},
               {"zeta", zeta},
               {"omega_n_rad_per_s", wn},
               {"f_n_Hz", fn},
               {"aperiodic", t.aperiodic()},
               {"transient_peak_lag_m", tr.peak_m},
               {"settling_time_s", tr.settling_s}};
    j["shop"] = {{"V_pr_mm_per_min", v_pr * 6e4},
                 {"v_T_mm_per_min", v_t * 6e4},
                 {"q_ss_um", q_ss * 1e6},
                 {"q_ss_axial_um", q_ss * std::cos(be) * 1e6},
                 {"q_ss_radial_um", q_ss * std::sin(be) * 1e6},
                 {"q_static_um", q_static * 1e6},
                 {"q_dynamic_um", q_dyn * 1e6},
                 {"zeta", zeta},
                 {"f_n_Hz", fn},
                 {"aperiodic", t.aperiodic()},
                 {"transient_peak_lag_um", tr.peak_m * 1e6},
                 {"settling_time_ms", tr.settling_s * 1e3}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf(
      "Hydraulic tracer slide, linearised (seed 002, (8)-(9))\n  %-34s %14s %-10s %14s %s\n", "",
      "SI", "", "shop", "");
  print_value(false, "carriage feed V_pr = s·n/60", v_pr, "m/s", v_pr * 6e4, "mm/min");
  print_value(false, "slide rate v_T on the cone", v_t, "m/s", v_t * 6e4, "mm/min");
  print_value(false, "steady lag q_ss (along slide)", q_ss, "m", q_ss * 1e6, "µm");
  print_value(false, "  axial component q·cos β", q_ss * std::cos(be), "m",
              q_ss * std::cos(be) * 1e6, "µm");
  print_value(false, "  radial component q·sin β", q_ss * std::sin(be), "m",
              q_ss * std::sin(be) * 1e6, "µm");
  print_value(false, "  static part P0/(E0·i)", q_static, "m", q_static * 1e6, "µm");
  print_value(false, "  dynamic part v_T/(C0·i)", q_dyn, "m", q_dyn * 1e6, "µm");
  print_value(false, "damping ratio ζ", zeta, "", zeta, "");
  print_value(false, "natural frequency ω_n/2π", fn, "Hz", fn, "Hz");
  std::printf("  %-34s %14s\n", "aperiodic (ζ ≥ 1)", t.aperiodic() ? "yes" : "no");
  print_value(false, "peak dynamic lag, cylinder→cone", tr.peak_m, "m", tr.peak_m * 1e6, "µm");
  print_value(false, "settling time (2 %)", tr.settling_s, "s", tr.settling_s * 1e3, "ms", true);
  return 0;
}

// One line for a command-line error CLI11 reports: the command it concerns, an unknown command
// named with the ones there are, a rejected value as "--flag VALUE: expected ... (what it is)".
std::string command_line_error(const CLI::App& app, const CLI::ParseError& e, int argc,
                               char** argv) {
  const CLI::App* cur = &app;
  std::vector<std::string> path;
  while (!cur->get_subcommands().empty()) {
    cur = cur->get_subcommands().front();
    path.push_back(cur->get_name());
  }
  std::string where;
  for (const auto& p : path) where += (where.empty() ? "" : " ") + p;
  std::string known;
  for (const auto* sub : cur->get_subcommands([](const CLI::App*) { return true; }))
    known += (known.empty() ? "" : ", ") + sub->get_name();
  if (!known.empty() && cur->get_subcommands().empty() && cur->get_require_subcommand_min() > 0) {
    // The first word that is neither an option nor the command path so far.
    std::size_t matched = 0;
    for (int i = 1; i < argc; ++i) {
      const std::string w = argv[i];
      if (w.empty() || w[0] == '-') continue;
      if (matched < path.size() && w == path[matched]) {
        ++matched;
        continue;
      }
      return "unknown command '" + (where.empty() ? w : where + " " + w) + "' (" + known + ")";
    }
    return (where.empty() ? "" : where + ": ") + "a command is required (" + known + ")";
  }
  std::string msg = e.what();
  if (dynamic_cast<const CLI::ValidationError*>(&e) && !msg.empty() && msg[0] == '-') {
    // "--d-mm: nan: expected ..." → "--d-mm nan: expected ... (spool diameter d)"
    const auto colon = msg.find(": ");
    const std::string name = msg.substr(0, colon);
    if (colon != std::string::npos) msg = name + " " + msg.substr(colon + 2);
    if (const CLI::Option* opt = cur->get_option_no_throw(name)) {
      std::string what = opt->get_description();
      what = what.substr(0, what.find(" ["));
      if (!what.empty()) msg += " (" + what + ")";
    }
  }
  for (auto& c : msg)
    if (c == '\n') c = ' ';
  return (where.empty() ? "" : where + ": ") + msg;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lathectl — automatic and adaptive lathe control: simulate, design, deploy"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("lathectl ") + LATHECTL_VERSION + " (commit " +
                                        LATHECTL_GIT_COMMIT + ")");
  // Where the seed, formula and block numbers of the help texts are explained (subcommands
  // inherit the footer; the ones with a page of their own name it).
  const auto doc = [](const std::string& page) {
    return "docs/" + page + " in the lathectl sources (installed: /usr/share/doc/lathectl/docs/" +
           page + ")";
  };
  app.footer(
      "Exit codes: 0 success; 1 internal failure; 2 bad input (one message naming file, line and "
      "key); 3 with --strict (run, demo): a claim not met, an alarm raised or a part not "
      "finished.\n"
      "Seed numbers (000–004), formula numbers such as (23) and block numbers such as \"sensor "
      "4\" refer to the five original documents, explained in " +
      doc("README.md") + ".");

  std::string scenario, out = "out";
  auto* run = app.add_subcommand(
      "run", "Run a scenario closed-loop and write summary.json, channels.csv, report.html");
  run->add_option("scenario", scenario, "scenario file (TOML)")->required();
  run->add_option("--out", out, "output directory")->capture_default_str();
  bool strict = false;
  run->add_flag("--strict", strict,
                "exit 3 when a claim is not met, an alarm fired (expected or not) or the part was "
                "not finished");
  run->footer("Scenario files: " + doc("scenario-reference.md") + ".");

  auto* check = app.add_subcommand("check", "Validate a scenario file without running it");
  check->add_option("scenario", scenario, "scenario file (TOML)")->required();
  check->footer("Scenario files: " + doc("scenario-reference.md") + ".");

  std::string demo_out = "demo-out", demo_dir = examples_dir();
  auto* demo = app.add_subcommand(
      "demo", "Run every example scenario and write an index.html linking the reports");
  demo->add_option("--out", demo_out, "output directory")->capture_default_str();
  demo->add_option("--examples", demo_dir, "directory of example scenarios")->capture_default_str();
  std::vector<std::string> demo_only;
  demo->add_option("names", demo_only,
                   "run only these examples (file names without .toml; default: all)");
  demo->add_flag("--strict", strict,
                 "exit 3 when any scenario has a claim not met, an alarm or an unfinished part");

  std::string lobes_file, lobes_out = "lobes-out";
  auto* lobes = app.add_subcommand(
      "lobes", "Stability lobes of a chatter model (frequency domain and semi-discretization)");
  lobes
      ->add_option("machine", lobes_file,
                   "machine file (TOML): [cutting], [[mode]] and/or [part], [speed], [lobes]")
      ->required();
  lobes->add_option("--out", lobes_out, "output directory")->capture_default_str();
  lobes->footer("Machine files: " + doc("machine-file-reference.md") + ".");

  auto* design = app.add_subcommand("design", "Design calculators from the papers' formulas");
  design->require_subcommand(1);
  // Number checks of every option: "VALUE: expected a finite number > 0"; the error handler
  // below makes the one line "--d-mm nan: expected a finite number > 0 (spool diameter d)".
  auto bounded = [](double lo, bool lo_open, double hi, const char* bound) {
    return CLI::Validator(
        [=](std::string& in) -> std::string {
          char* end = nullptr;
          const double v = std::strtod(in.c_str(), &end);
          const bool ok = end != in.c_str() && *end == '\0' && std::isfinite(v) &&
                          (lo_open ? v > lo : v >= lo) && v <= hi;
          if (ok) return {};
          return in + ": expected a finite number" + (*bound ? std::string(" ") + bound : "");
        },
        *bound ? bound : "finite");
  };
  const double kInf = std::numeric_limits<double>::infinity();
  const CLI::Validator positive = bounded(0.0, true, kInf, "> 0"),
                       non_negative = bounded(0.0, false, kInf, ">= 0"),
                       finite = bounded(-kInf, false, kInf, ""),
                       coefficient = bounded(0.0, true, 1.0, "in (0, 1]");
  design::PulseRegulatorInput pr;
  double d_mm = 8, h_mm = 0.04, dp_MPa = 0.5, rho = 870, mu = 0.65, dt_ms = 10, T_ms = 0, f_Hz = 0,
         F_cm2 = 20, leak = 0, Py = 0, dPy = 0;
  bool as_json = false;
  auto* preg = design->add_subcommand(
      "pulse-regulator",
      "Seed 000: Q (1), Ka (2), S (3), Δh (4), Kf (6), Δf and duty of a pulsed flow regulator");
  preg->footer("Seed 000 and its formulas (1)-(7): " + doc("system-a-pulse-feed.md") + ".");
  preg->add_option("--d-mm", d_mm, "spool diameter d [mm]")
      ->capture_default_str()
      ->check(positive);
  preg->add_option("--h-mm", h_mm, "slot opening h [mm]")
      ->capture_default_str()
      ->check(positive);
  preg->add_option("--dp-MPa", dp_MPa, "pressure drop Δp across the regulator [MPa]")
      ->capture_default_str()
      ->check(positive);
  preg->add_option("--rho", rho, "oil density ρ [kg/m³]")
      ->capture_default_str()
      ->check(positive);
  preg->add_option("--mu", mu, "discharge coefficient μ")
      ->capture_default_str()
      ->check(coefficient);
  preg->add_option("--dt-ms", dt_ms, "pulse width Δt [ms]")
      ->capture_default_str()
      ->check(positive);
  auto* oT = preg->add_option("--T-ms", T_ms, "pulse period T [ms]")->check(positive);
  auto* of = preg->add_option("--f-Hz", f_Hz, "pulse frequency f [Hz] (instead of T)")
                 ->check(positive);
  oT->excludes(of);
  preg->add_option("--F-cm2", F_cm2, "effective piston area F [cm²]")
      ->capture_default_str()
      ->check(positive);
  preg->add_option("--leak", leak, "leakage K_leak [cm³/min per MPa]")
      ->capture_default_str()
      ->check(non_negative);
  preg->add_option("--Py", Py, "radial cutting force Py [N]")->capture_default_str()->check(finite);
  preg->add_option("--dPy", dPy, "force change ΔPy [N]")->capture_default_str()->check(finite);
  preg->add_flag("--json", as_json, "print JSON (SI and shop units)");

  AdaptiveSpeedArgs asp;
  auto* aspd = design->add_subcommand(
      "adaptive-speed",
      "Seed 004: optimal speed V_opt = V_p·(S_p/S)^yv; handbook tool life T and speed for a "
      "life; feed per revolution. Each result is computed when its inputs are given");
  aspd->footer("Seed 004 and V_opt: " + doc("system-e-adaptive.md") +
               "; materials: " + doc("materials-reference.md") + ".");
  double Vp = 0, Sp = 0, yv = 0, S = 0, Cv = 0, m = 0, xv = 0, t = 0, s = 0, V = 0, T = 0, F = 0,
         n = 0;
  struct Bound {
    CLI::Option* opt;
    double* value;
    std::optional<double>* into;
  };
  std::vector<Bound> bound;
  auto num = [&](const char* name, double& v, std::optional<double>& into, const char* help,
                 const CLI::Validator& validator) {
    bound.push_back({aspd->add_option(name, v, help)->check(validator), &v, &into});
  };
  num("--Vp", Vp, asp.Vp, "computed (planned) cutting speed V_p [m/min]", positive);
  num("--Sp", Sp, asp.Sp, "computed (planned) feed S_p [mm/rev]", positive);
  num("--yv", yv, asp.yv, "feed exponent y_v of the tool-life formula", non_negative);
  num("--S", S, asp.S, "current feed S [mm/rev] (for V_opt)", positive);
  num("--Cv", Cv, asp.Cv, "tool-life coefficient Cv", positive);
  num("--m", m, asp.m, "tool-life exponent m", positive);
  num("--xv", xv, asp.xv, "depth exponent x_v", non_negative);
  num("--t", t, asp.t, "depth of cut t [mm]", positive);
  num("--s", s, asp.s, "feed s [mm/rev] (for tool life and speed for life)", positive);
  num("--V", V, asp.V, "cutting speed V [m/min] → tool life T [min]", positive);
  num("--T-target", T, asp.T, "target tool life T [min] → speed for that life [m/min]", positive);
  num("--F", F, asp.F, "feed rate F [mm/min] (with --n → feed per revolution)", positive);
  num("--n", n, asp.n, "spindle speed n [rpm]", positive);
  aspd->add_option("--material", asp.material,
                   "material in data/materials.toml: Cv, m, xv, yv from its tool-life range "
                   "containing the feed (--s; --S for V_opt); explicit options win");
  aspd->add_flag("--json", asp.json, "print JSON (inputs, coefficients used, results)");

  GaugeArgs ga;
  auto* gauge = design->add_subcommand(
      "gauge",
      "Seed 003: vibro-contact in-process gauge — free amplitude A0, gain K, threshold S_th (23), "
      "end time t_k (22), filtered noise D_y (25), size scatter σ_x and Cp");
  gauge->footer("Seed 003 and its formulas (20)-(25): " + doc("system-d-gauging.md") + ".");
  auto gopt = [&](const char* name, double& v, const char* help, const CLI::Validator& validator) {
    gauge->add_option(name, v, help)->capture_default_str()->check(validator);
  };
  gopt("--supply-V", ga.supply_V, "electromagnet supply amplitude V [V]", positive);
  gopt("--supply-Hz", ga.supply_Hz, "supply frequency ω/2π [Hz] (the probe runs at 2ω)", positive);
  gopt("--coil-turns", ga.coil_turns, "electromagnet coil turns W", positive);
  gopt("--coil-ohm", ga.coil_ohm, "coil resistance r [Ω]", positive);
  gopt("--coil-H", ga.coil_H, "coil inductance L [H]", positive);
  gopt("--force-coeff", ga.force_coeff, "magnet force coefficient a, F = a·Φ² [N/Wb²]", positive);
  gopt("--probe-mass-g", ga.probe_mass_g, "probe mass M [g]", positive);
  gopt("--probe-damping", ga.probe_damping, "probe damping h [N·s/m]", non_negative);
  gopt("--probe-stiffness-N-per-mm", ga.probe_stiffness_N_per_mm, "probe spring stiffness k [N/mm]",
       positive);
  gopt("--generator", ga.generator, "sensor-generator constant K_g [V per m/s]", positive);
  gopt("--generator-ms", ga.generator_ms, "generator time constant T_g [ms]", non_negative);
  gopt("--filter-ms", ga.filter_ms, "smoothing filter time constant T_f [ms]", positive);
  gopt("--relay-ms", ga.relay_ms, "relay/command response time t_r [ms]", non_negative);
  gopt("--allowance-um", ga.allowance_um, "controlled allowance at the start m_x [µm]", positive);
  gopt("--removal-um-per-s", ga.removal_um_per_s, "removal rate a [µm/s]", positive);
  gopt("--target-um", ga.target_um, "final controlled size x_k [µm]", non_negative);
  gopt("--noise-sigma-um", ga.noise_sigma_um, "disturbance σ = sqrt(D) [µm]", non_negative);
  gopt("--noise-beta", ga.noise_beta, "disturbance correlation decay β, R = D·e^(−β|τ|) [1/s]",
       non_negative);
  double gauge_tol_um = 0;
  auto* gauge_tol = gauge
                        ->add_option("--tolerance-um", gauge_tol_um,
                                     "± size tolerance [µm] → also Cp = 2·tol/(6·σ_x)")
                        ->check(positive);
  gauge->add_flag("--json", ga.json, "print JSON (inputs, SI and shop units)");

  TracerArgs ta;
  auto* tracer = design->add_subcommand(
      "tracer",
      "Seed 002: linearised hydraulic tracer slide — steady lag on a cone (P0/E0 + v_T/C0)/i, "
      "damping ratio, natural frequency, transient lag and settling at a cylinder→cone change");
  tracer->footer("Seed 002 and its formulas (8)-(9): " + doc("system-c-tracer.md") + ".");
  auto topt = [&](const char* name, double& v, const char* help, const CLI::Validator& validator) {
    tracer->add_option(name, v, help)->capture_default_str()->check(validator);
  };
  topt("--E0", ta.E0_N_per_mm, "stiffness E0 = ∂P/∂h [N per mm of spool opening]", positive);
  topt("--C0", ta.C0_per_s, "velocity gain C0 = ∂V/∂h [1/s]", positive);
  topt("--M", ta.mass_kg, "reduced moving mass M [kg]", positive);
  topt("--i", ta.lever, "lever ratio i (spool opening per stylus deflection)", positive);
  topt("--P0", ta.P0_N, "cutting + dry friction force P0 [N]", non_negative);
  tracer->add_option("--beta-deg", ta.beta_deg, "guide inclination β to the axis [deg]")
      ->capture_default_str()
      ->check(finite);
  tracer->add_option("--alpha-deg", ta.alpha_deg, "template cone angle α [deg]")
      ->capture_default_str()
      ->check(finite);
  topt("--s", ta.feed_mm_per_rev, "feed s [mm/rev]", positive);
  topt("--n", ta.rpm, "spindle speed n [rpm]", positive);
  tracer->add_flag("--json", ta.json, "print JSON (inputs, SI and shop units)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // A bad command line is bad input like any other: one line naming the command and the flag.
    std::cerr << "error: " << command_line_error(app, e, argc, argv) << "\n";
    return 2;
  }

  try {
    if (*run) return cmd_run(scenario, out, strict);
    if (*check) return cmd_check(scenario);
    if (*demo) return cmd_demo(demo_out, demo_dir, demo_only, strict);
    if (*lobes) {
      const auto in = b_chatter::load_lobes_input(lobes_file);
      io::prepare_output_dir(lobes_out, "--out");
      nlohmann::json j;
      {
        io::Progress progress("lobes");
        j = b_chatter::run_lobes(in, lobes_out, &progress);
      }
      for (const auto& w : j["warnings"]) std::cerr << "warning: " << w.get<std::string>() << "\n";
      std::cout << "critical depth " << j["critical_depth_mm"].get<double>() << " mm at "
                << j["chatter_frequency_Hz"].get<double>() << " Hz; " << j["lobes"].size()
                << " lobes (" << j["lobes_with_minimum_in_range"].get<int>()
                << " with their minimum inside the speed range) → "
                << (std::filesystem::path(lobes_out) / "lobes.html").string() << "\n";
      return 0;
    }
    if (*aspd) {
      for (const auto& b : bound)
        if (b.opt->count() > 0) *b.into = *b.value;
      return cmd_adaptive_speed(asp);
    }
    if (*tracer) return cmd_tracer(ta);
    if (*gauge) {
      if (gauge_tol->count() > 0) ga.tolerance_um = gauge_tol_um;
      return cmd_gauge(ga);
    }
    if (*preg) {
      if (T_ms <= 0 && f_Hz <= 0)
        throw io::InputError("design pulse-regulator: give --T-ms or --f-Hz");
      pr.spool_diameter_m = d_mm * 1e-3;
      pr.slot_m = h_mm * 1e-3;
      pr.pressure_drop_Pa = dp_MPa * 1e6;
      pr.density_kg_per_m3 = rho;
      pr.discharge_coefficient = mu;
      pr.pulse_width_s = dt_ms * 1e-3;
      pr.period_s = T_ms > 0 ? T_ms * 1e-3 : 1.0 / f_Hz;
      pr.piston_area_m2 = F_cm2 * 1e-4;
      pr.leak_m3_per_s_Pa = leak * 1e-6 / 60.0 / 1e6;
      pr.force_N = Py;
      pr.force_change_N = dPy;
      design::PulseRegulatorResult r;
      try {
        r = design::pulse_regulator(pr);
      } catch (const std::invalid_argument& e) {
        throw io::InputError(std::string("design pulse-regulator: ") + e.what());
      }
      if (as_json) {
        nlohmann::json j;
        j["si"] = {{"Q_m3_per_s", r.flow_m3_per_s},
                   {"Ka_m2_per_s", r.ka_m2_per_s},
                   {"Kf_m3", r.kf_m3},
                   {"S_m_per_s", r.feed_m_per_s},
                   {"S_no_leak_m_per_s", r.feed_no_leak_m_per_s},
                   {"leak_m3_per_s", r.leak_m3_per_s},
                   {"dh_m", r.slot_change_m},
                   {"df_Hz", r.frequency_change_Hz},
                   {"duty", r.duty},
                   {"f_Hz", r.frequency_Hz}};
        j["shop"] = {{"Q_cm3_per_min", r.flow_m3_per_s * 6e7},
                     {"Ka_cm3_per_min_per_mm", r.ka_m2_per_s * 6e4},
                     {"Kf_cm3_per_min_per_Hz", r.kf_m3 * 6e7},
                     {"S_mm_per_min", r.feed_m_per_s * 6e4},
                     {"S_no_leak_mm_per_min", r.feed_no_leak_m_per_s * 6e4},
                     {"leak_cm3_per_min", r.leak_m3_per_s * 6e7},
                     {"dh_um", r.slot_change_m * 1e6},
                     {"df_Hz", r.frequency_change_Hz},
                     {"duty_pct", r.duty * 100}};
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("Pulsed flow regulator (seed 000)\n  %-34s %14s %-10s %14s %s\n", "", "SI", "",
                    "shop", "");
        print_value(false, "mean flow Q (1)", r.flow_m3_per_s, "m³/s", r.flow_m3_per_s * 6e7,
                    "cm³/min");
        print_value(false, "AIM gain Ka (2)", r.ka_m2_per_s, "m²/s", r.ka_m2_per_s * 6e4,
                    "cm³/min per mm");
        print_value(false, "FIM gain Kf (6)", r.kf_m3, "m³", r.kf_m3 * 6e7, "cm³/min per Hz");
        print_value(false, "feed without leakage Q/F", r.feed_no_leak_m_per_s, "m/s",
                    r.feed_no_leak_m_per_s * 6e4, "mm/min");
        print_value(false, "leakage K_leak·Py/F", r.leak_m3_per_s, "m³/s", r.leak_m3_per_s * 6e7,
                    "cm³/min");
        print_value(false, "feed S (3)", r.feed_m_per_s, "m/s", r.feed_m_per_s * 6e4, "mm/min");
        print_value(false, "slot correction Δh (4)", r.slot_change_m, "m", r.slot_change_m * 1e6,
                    "µm");
        print_value(false, "frequency correction Δf", r.frequency_change_Hz, "Hz",
                    r.frequency_change_Hz, "Hz");
        print_value(false, "duty Δt/T", r.duty, "", r.duty * 100, "%");
        print_value(false, "frequency f", r.frequency_Hz, "Hz", r.frequency_Hz, "Hz", true);
      }
      return 0;
    }
  } catch (const io::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return 1;
  }
  return 1;
}
