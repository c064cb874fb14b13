// `lathectl design adaptive-speed`: seed 004's V_opt and the handbook tool-life law, shop units
// (design/adaptive_speed.hpp). Every input and output is one row below; each result is computed
// when its group of inputs is complete.
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/cutting/feed_range.hpp"
#include "lathectl/design/adaptive_speed.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"

namespace lathectl::cli {
namespace {

using io::Range;
using Opt = std::optional<double>;

struct Args {                 // shop units, as the flags; none has a default
  Opt Vp, Sp, yv, S;          // V_opt group [m/min, mm/rev, -, mm/rev]
  Opt Cv, m, xv, t, s, V, T;  // tool-life groups: Cv, m, xv [-], t [mm], s [mm/rev], V, T
  Opt F, n;                   // feed per revolution group [mm/min, rpm]
  Opt D;                      // workpiece diameter [mm] → spindle speed for V_opt
  std::string material;
  bool json = false;
};

// Ranges: what a lathe cuts (speeds of 1 mm/min to 100 km/min, feeds of 0.1 µm to 100 mm/rev,
// depths of 1 µm to 100 mm, lives of 6 s to 10⁵ min) and the handbook's exponents (m of 0.01 to
// 10, x_v and y_v of 0 to 10): beyond them the power laws overflow to inf.
const Range kSpeed = Range::closed(1e-3, 1e5), kFeed = Range::closed(1e-4, 100),
            kExponent = Range::closed(0, 10);
const Input<Args> kInputs[] = {
    {"--Vp", {"Vp_m_per_min", kSpeed, "computed (planned) cutting speed V_p"}, "m/min", &Args::Vp},
    {"--Sp", {"Sp_mm_per_rev", kFeed, "computed (planned) feed S_p"}, "mm/rev", &Args::Sp},
    {"--yv", {"yv", kExponent, "feed exponent y_v of the tool-life formula"}, "", &Args::yv},
    {"--S", {"S_mm_per_rev", kFeed, "current feed S"}, "mm/rev", &Args::S, "(for V_opt)"},
    {"--Cv", {"Cv", Range::closed(1e-3, 1e6), "tool-life coefficient Cv"}, "", &Args::Cv},
    {"--m", {"m", Range::closed(0.01, 10), "tool-life exponent m"}, "", &Args::m},
    {"--xv", {"xv", kExponent, "depth exponent x_v"}, "", &Args::xv},
    {"--t", {"t_mm", Range::closed(1e-3, 100), "depth of cut t"}, "mm", &Args::t},
    {"--s",
     {"s_mm_per_rev", kFeed, "feed s"},
     "mm/rev",
     &Args::s,
     "(for tool life and speed for life)"},
    {"--V", {"V_m_per_min", kSpeed, "cutting speed V"}, "m/min", &Args::V, "→ tool life T [min]"},
    {"--T-target",
     {"T_target_min", Range::closed(0.1, 1e5), "target tool life T"},
     "min",
     &Args::T,
     "→ speed for that life [m/min]"},
    {"--F",
     {"F_mm_per_min", Range::closed(1e-3, 1e6), "feed rate F"},
     "mm/min",
     &Args::F,
     "(with --n → feed per revolution)"},
    {"--n", {"n_rpm", Range::closed(1e-2, 1e6), "spindle speed n"}, "rpm", &Args::n},
    {"--D-mm",
     {"D_mm", Range::closed(0.1, 1e5), "workpiece diameter D"},
     "mm",
     &Args::D,
     "(with V_opt → its spindle speed)"},
};

struct Result {
  Opt v_opt, n_opt, life, v_life, feed;
};
// Shop units only (the handbook's), under "results" in the JSON.
const Output<Result> kOutputs[] = {
    {"optimal cutting speed V_opt", "", "", "V_opt_m_per_min", "m/min", 1, &Result::v_opt},
    {"spindle speed n = 1000·V_opt/(π·D)", "", "", "n_opt_rpm", "rpm", 1, &Result::n_opt},
    {"tool life T at V", "", "", "tool_life_min", "min", 1, &Result::life},
    {"speed V_T for the target life", "", "", "speed_for_life_m_per_min", "m/min", 1,
     &Result::v_life},
    {"feed per revolution s = F/n", "", "", "feed_per_rev_mm_per_rev", "mm/rev", 1, &Result::feed},
};

// Extended-Taylor coefficients for one calculation: explicit options win; the rest come from the
// material's tool-life range that contains the calculation's feed (as CuttingModel chooses it).
struct TaylorCoefficients {
  Opt Cv, m, xv, yv;
  const cutting::ToolLifeRange* range = nullptr;  // the material range used, if any
};


TaylorCoefficients coefficients(const Args& a, const cutting::Material* mat, Opt feed) {
  TaylorCoefficients c{a.Cv, a.m, a.xv, a.yv, nullptr};
  if (mat && feed) {
    const auto& r = cutting::feed_range(mat->tool_life, mat->tool_life_ranges, *feed);
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
std::string missing(std::initializer_list<std::pair<const Opt*, const char*>> l) {
  std::string out;
  for (const auto& [v, name] : l)
    if (!v->has_value()) out += (out.empty() ? "" : " ") + std::string(name);
  return out;
}

// --json: the inputs, the coefficients used (and the material range they came from), the results.
void print_json(const Args& a, const cutting::Material* mat, const TaylorCoefficients& c_opt,
                const TaylorCoefficients& c_life, bool do_opt, bool do_taylor, const Result& r) {
  nlohmann::json in = inputs_json<Args>(a, kInputs);
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
  nlohmann::json j, used = nlohmann::json::object();
  if (do_opt) used["V_opt"] = coeffs(c_opt, false);
  if (do_taylor) used["tool_life"] = coeffs(c_life, true);
  j["inputs"] = in;
  j["coefficients"] = used;
  j["results"] = nlohmann::json::object();
  outputs_json<Result>(j, r, kOutputs, "si", "results");
  std::cout << j.dump(2) << "\n";
}

int compute(const Args& a) {
  const std::string who = "design adaptive-speed: ";
  io::MaterialLibrary lib;
  const cutting::Material* mat = nullptr;
  if (!a.material.empty()) mat = &tool_life_material(lib, a.material, who);
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
  const std::string miss_feed = missing({{&a.F, "--F"}, {&a.n, "--n"}});
  const bool do_opt = miss_opt.empty();
  const bool do_life = miss_taylor.empty() && a.V;
  const bool do_speed = miss_taylor.empty() && a.T;
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

  Result r;
  try {
    if (do_opt) r.v_opt = design::optimal_speed(*a.Vp, *a.Sp, *c_opt.yv, *a.S);
    if (r.v_opt && a.D) r.n_opt = 1000.0 * *r.v_opt / (3.14159265358979323846 * *a.D);
    if (do_life)
      r.life =
          design::tool_life_min(*c_life.Cv, *c_life.m, *c_life.xv, *c_life.yv, *a.V, *a.t, *a.s);
    if (do_speed)
      r.v_life =
          design::speed_for_life(*c_life.Cv, *c_life.m, *c_life.xv, *c_life.yv, *a.T, *a.t, *a.s);
    if (do_feed) r.feed = design::feed_per_rev(*a.F, *a.n);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(who + e.what());
  }
  require_finite<Result>(who, r, kOutputs,
                         "--Vp, --Sp, --S, --yv (V_opt); --Cv, --m, --xv, --yv, --t, --s, --V, "
                         "--T-target (tool life)");

  if (a.json) {
    print_json(a, mat, c_opt, c_life, do_opt, do_life || do_speed, r);
    return 0;
  }
  auto row = [&](const Output<Result>& o) { print_shop_row(r, o); };
  auto source = [&](const TaylorCoefficients& c) {
    if (!c.range) return std::string("options");
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s, feed range <= %g mm/rev", mat->name.c_str(),
                  c.range->feed_max_mm_per_rev);
    return std::string(buf);
  };
  std::printf("Adaptive cutting speed (seed 004) and tool life (extended Taylor, handbook)\n");
  if (do_opt)
    std::printf("  V_opt = V_p·(S_p/S)^yv with yv = %g (%s)\n", *c_opt.yv,
                a.yv ? "options" : source(c_opt).c_str());
  row(kOutputs[0]);
  row(kOutputs[1]);
  if (do_life || do_speed)
    std::printf("  V = Cv/(T^m·t^xv·s^yv) with Cv = %g, m = %g, xv = %g, yv = %g (%s)\n",
                *c_life.Cv, *c_life.m, *c_life.xv, *c_life.yv, source(c_life).c_str());
  for (std::size_t k = 2; k < std::size(kOutputs); ++k) row(kOutputs[k]);
  return 0;
}

void add(CLI::App& sub, Commands& out) {
  add_material_calculator<Args>(
      sub, out, kInputs,
      "Seed 004 and V_opt: " + doc("system-e-adaptive.md") +
          "; materials: " + doc("materials-reference.md") + ".",
      "material in data/materials.toml: Cv, m, xv, yv from its tool-life range containing the "
      "feed (--s; --S for V_opt); explicit options win",
      "print JSON (inputs, coefficients used, results)", &compute);
}

std::string reference() {
  return "Inputs (`--material NAME` supplies Cv, m, xv, yv from data/materials.toml):\n\n" +
         inputs_markdown<Args>(kInputs) + "\nResults (`--json`: `results`, shop units):\n\n" +
         outputs_markdown<Result>(kOutputs);
}

std::vector<CalculatorInput> inputs() { return input_rows<Args>(kInputs); }

}  // namespace

const Calculator kAdaptiveSpeed{
    "adaptive-speed",
    "Seed 004: optimal speed V_opt = V_p·(S_p/S)^yv; handbook tool life T and speed for a life; "
    "feed per revolution. Each result is computed when its inputs are given",
    &add, &reference, &inputs};

}  // namespace lathectl::cli
