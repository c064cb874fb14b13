// lathectl — command-line front end: run scenarios, validate them, run the demo, and the papers'
// design calculators. Exit codes: 0 success, 2 bad input (one clear message), 1 internal failure.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <thread>
#include <vector>

#include "lathectl/design/pulse_regulator.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"

namespace fs = std::filesystem;
using namespace lathectl;

namespace {

std::string examples_dir() {
  if (const char* env = std::getenv("LATHECTL_EXAMPLES_DIR"); env && *env) return env;
  if (fs::exists(LATHECTL_EXAMPLES_DIR)) return LATHECTL_EXAMPLES_DIR;
  return LATHECTL_INSTALLED_EXAMPLES_DIR;
}

int cmd_run(const std::string& scenario, const std::string& out) {
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = io::load_scenario(scenario, lib);
  const auto result = io::run_scenario(sc);
  io::write_outputs(result, out);
  std::cout << sc.name << ": " << result.headline << "\n  → "
            << (fs::path(out) / "report.html").string() << "\n";
  return 0;
}

int cmd_check(const std::string& scenario) {
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = io::load_scenario(scenario, lib);
  std::cout << scenario << ": OK (system " << sc.system << ", \"" << sc.name << "\", "
            << sc.run.duration_s << " s at step " << sc.run.step_s << " s)\n";
  return 0;
}

int cmd_demo(const std::string& out, const std::string& dir) {
  const auto lib = io::MaterialLibrary::load_default();
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw io::InputError(dir + ": no example scenarios (*.toml) found");
  // Parse all first: nothing runs on a half-read example set.
  std::vector<io::Scenario> scenarios;
  for (const auto& f : files) scenarios.push_back(io::load_scenario(f.string(), lib));

  std::vector<io::IndexEntry> entries(scenarios.size());
  std::vector<std::string> errors(scenarios.size());
  std::atomic<std::size_t> next{0};
  std::mutex print;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < scenarios.size();) {
      try {
        const auto r = io::run_scenario(scenarios[i]);
        const fs::path sub = fs::path(out) / scenarios[i].name;
        io::write_outputs(r, sub);
        entries[i] = {scenarios[i].name + " — " + scenarios[i].description.substr(0, 120),
                      scenarios[i].name + "/report.html", r.headline};
        std::lock_guard lock(print);
        std::cout << "  " << scenarios[i].name << ": " << r.headline << "\n";
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    }
  };
  const unsigned n = std::max(1u, std::min(std::thread::hardware_concurrency(), 8u));
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < n; ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  for (const auto& e : errors)
    if (!e.empty()) throw std::runtime_error(e);
  io::write_file_atomic(fs::path(out) / "index.html",
                        io::render_index_html("lathectl demo — example scenarios", entries));
  std::cout << "demo: " << scenarios.size() << " scenarios → "
            << (fs::path(out) / "index.html").string() << "\n";
  return 0;
}

void print_value(bool json_first, const char* key, double si, const char* si_unit, double shop,
                 const char* shop_unit, bool last = false) {
  (void)json_first;
  std::printf("  %-34s %14.6g %-10s %14.6g %s%s", key, si, si_unit, shop, shop_unit,
              last ? "\n" : "\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lathectl — automatic and adaptive lathe control: simulate, design, deploy"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lathectl 0.1.0");

  std::string scenario, out = "out";
  auto* run = app.add_subcommand(
      "run", "Run a scenario closed-loop and write summary.json, channels.csv, report.html");
  run->add_option("scenario", scenario, "scenario file (TOML)")->required();
  run->add_option("--out", out, "output directory")->capture_default_str();

  auto* check = app.add_subcommand("check", "Validate a scenario file without running it");
  check->add_option("scenario", scenario, "scenario file (TOML)")->required();

  std::string demo_out = "demo-out", demo_dir = examples_dir();
  auto* demo = app.add_subcommand(
      "demo", "Run every example scenario and write an index.html linking the reports");
  demo->add_option("--out", demo_out, "output directory")->capture_default_str();
  demo->add_option("--examples", demo_dir, "directory of example scenarios")->capture_default_str();

  auto* design = app.add_subcommand("design", "Design calculators from the papers' formulas");
  design->require_subcommand(1);
  design::PulseRegulatorInput pr;
  double d_mm = 8, h_mm = 0.04, dp_MPa = 0.5, rho = 870, mu = 0.65, dt_ms = 10, T_ms = 0, f_Hz = 0,
         F_cm2 = 20, leak = 0, Py = 0, dPy = 0;
  bool as_json = false;
  auto* preg = design->add_subcommand(
      "pulse-regulator",
      "Seed 000: Q (1), Ka (2), S (3), Δh (4), Kf (6), Δf and duty of a pulsed flow regulator");
  preg->add_option("--d-mm", d_mm, "spool diameter d [mm]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  preg->add_option("--h-mm", h_mm, "slot opening h [mm]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  preg->add_option("--dp-MPa", dp_MPa, "pressure drop Δp across the regulator [MPa]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  preg->add_option("--rho", rho, "oil density ρ [kg/m³]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  preg->add_option("--mu", mu, "discharge coefficient μ")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  preg->add_option("--dt-ms", dt_ms, "pulse width Δt [ms]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  auto* oT = preg->add_option("--T-ms", T_ms, "pulse period T [ms]")->check(CLI::PositiveNumber);
  auto* of = preg->add_option("--f-Hz", f_Hz, "pulse frequency f [Hz] (instead of T)")
                 ->check(CLI::PositiveNumber);
  oT->excludes(of);
  preg->add_option("--F-cm2", F_cm2, "effective piston area F [cm²]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  preg->add_option("--leak", leak, "leakage K_leak [cm³/min per MPa]")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  preg->add_option("--Py", Py, "radial cutting force Py [N]")->capture_default_str();
  preg->add_option("--dPy", dPy, "force change ΔPy [N]")->capture_default_str();
  preg->add_flag("--json", as_json, "print JSON (SI and shop units)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    if (*run) return cmd_run(scenario, out);
    if (*check) return cmd_check(scenario);
    if (*demo) return cmd_demo(demo_out, demo_dir);
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
