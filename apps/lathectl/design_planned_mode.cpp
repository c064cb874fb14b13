// `lathectl design planned-mode`: seed 004's setters 15 and 18, the planned feed S_p and speed
// V_p, computed by the handbook from the material's tables (design::planned_mode,
// design/adaptive_speed.hpp). Every input and output is one row below.
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/design/adaptive_speed.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"

namespace lathectl::cli {
namespace {

using io::Range;
using Opt = std::optional<double>;

struct Args {  // shop units, as the flags; the initial values are the defaults
  Opt t;                       // planned depth [mm] (required)
  double T = 60.0;             // planned tool life [min]
  Opt force, power, Rz;        // limits [N, kW, µm]
  double r = 0.8;              // nose radius [mm]
  double s_min = 0.05, s_max = 0.8;
  double h = 1.0;              // hardness (strength) factor
  Opt D;                       // diameter [mm] → spindle speed
  std::string material;
  bool json = false;
};

// Ranges: what a lathe turns (depths of 1 µm to 100 mm, feeds of 0.1 µm to 100 mm/rev, tool
// lives of 6 s to 10⁵ min, parts of 0.1 mm to 100 m), and a hardness factor within a decade
// either way of the material's: beyond them the handbook's power laws give inf (a tool life of
// 1e-300 min made V_p and the spindle speed inf rpm, printed with exit 0).
const Input<Args> kInputs[] = {
    {"--t", {"t_mm", Range::closed(1e-3, 100), "planned depth of cut t_p"}, "mm", &Args::t, "(required)"},
    {"--T-life", {"T_min", Range::closed(0.1, 1e5), "planned tool life T"}, "min", &Args::T},
    {"--force-limit",
     {"force_limit_N", Range{0.0, 1e7, true, false}, "largest tangential force Pz (setter 6)"},
     "N",
     &Args::force},
    {"--power-limit", {"power_limit_kW", Range{0.0, 1e4, true, false}, "largest cutting power Pz·V"}, "kW", &Args::power},
    {"--Rz-limit", {"Rz_limit_um", Range{0.0, 1e4, true, false}, "largest theoretical roughness s²/(8r)"}, "µm", &Args::Rz},
    {"--r-mm", {"r_mm", Range::closed(0.01, 100), "tool nose radius r"}, "mm", &Args::r},
    {"--s-min", {"s_min_mm_per_rev", Range::closed(1e-4, 100), "smallest feed (setter 10)"}, "mm/rev", &Args::s_min},
    {"--s-max", {"s_max_mm_per_rev", Range::closed(1e-4, 100), "largest feed (setter 9)"}, "mm/rev", &Args::s_max},
    {"--hardness",
     {"hardness_factor", Range::closed(0.1, 10), "strength of the part relative to the material's"},
     "",
     &Args::h,
     "(Kp = h^kmp_exponent, Kv = h^(−kmv_exponent))"},
    {"--D-mm", {"D_mm", Range::closed(0.1, 1e5), "workpiece diameter D"}, "mm", &Args::D, "(→ spindle speed)"},
};

struct Result {
  double Sp = 0, Vp = 0, Pz = 0, P = 0, Rz = 0, mrr = 0;
  Opt n;
};
const Output<Result> kOutputs[] = {
    {"planned feed S_p (setter 15)", "", "", "Sp_mm_per_rev", "mm/rev", 1, &Result::Sp},
    {"planned speed V_p (setter 18)", "", "", "Vp_m_per_min", "m/min", 1, &Result::Vp},
    {"spindle speed n = 1000·V_p/(π·D)", "", "", "n_rpm", "rpm", 1, &Result::n},
    {"force Pz at t_p, S_p, V_p", "", "", "Pz_N", "N", 1, &Result::Pz},
    {"cutting power Pz·V_p", "", "", "power_kW", "kW", 1, &Result::P},
    {"theoretical roughness Rz", "", "", "Rz_um", "µm", 1, &Result::Rz},
    {"removal rate t·S_p·V_p", "", "", "mrr_cm3_per_min", "cm³/min", 1, &Result::mrr},
};

const char* limit_name(design::PlanLimit l) {
  switch (l) {
    case design::PlanLimit::Force: return "force limit";
    case design::PlanLimit::Power: return "power limit";
    case design::PlanLimit::Roughness: return "roughness limit";
    case design::PlanLimit::FeedMax: break;
  }
  return "largest feed";
}

int compute(const Args& a) {
  const std::string who = "design planned-mode: ";
  if (!a.t) throw io::InputError(who + "give the planned depth --t");
  if (a.material.empty()) throw io::InputError(who + "give --material (its handbook tables)");
  io::MaterialLibrary lib;
  const cutting::Material* mat = &tool_life_material(lib, a.material, who);
  design::PlannedModeInput in;
  for (int i = 0; i < mat->tool_life_ranges; ++i) {
    const auto& r = mat->tool_life[static_cast<std::size_t>(i)];
    in.life[static_cast<std::size_t>(i)] = {r.feed_max_mm_per_rev, r.Cv, r.m, r.xv, r.yv};
  }
  in.ranges = mat->tool_life_ranges;
  in.kv = std::pow(a.h, -mat->kmv_exponent);
  in.Cp = mat->Pz.Cp;
  in.x = mat->Pz.x;
  in.y = mat->Pz.y;
  in.n = mat->Pz.n;
  in.kp = std::pow(mat->strength / mat->strength_base * a.h, mat->kmp_exponent);
  in.depth_mm = *a.t;
  in.life_min = a.T;
  if (!(a.s_min <= a.s_max))
    throw io::InputError(who + "--s-min " + format_number(a.s_min) + " mm/rev exceeds --s-max " +
                         format_number(a.s_max) + " mm/rev: the feed range is empty");
  in.feed_min_mm_per_rev = a.s_min;
  in.feed_max_mm_per_rev = a.s_max;
  const double inf = std::numeric_limits<double>::infinity();
  in.force_limit_N = a.force.value_or(inf);
  in.power_limit_kW = a.power.value_or(inf);
  in.Rz_limit_um = a.Rz.value_or(inf);
  in.nose_radius_mm = a.r;
  design::PlannedMode pm;
  try {
    pm = design::planned_mode(in);
  } catch (const std::invalid_argument& e) {
    // The one rule between flags the handbook can break: name them.
    const std::string m = e.what();
    const char* flag = m.find("force limit") != std::string::npos   ? "--force-limit"
                       : m.find("power limit") != std::string::npos ? "--power-limit"
                       : m.find("roughness limit") != std::string::npos ? "--Rz-limit"
                                                                        : nullptr;
    if (flag)
      throw io::InputError(who + m + " (" + flag + "): even --s-min " + format_number(a.s_min) +
                           " mm/rev breaks it at t_p = " + format_number(*a.t) +
                           " mm; raise " + flag + " or lower --s-min or --t");
    throw io::InputError(who + m);
  }
  Result r{pm.feed_mm_per_rev, pm.speed_m_per_min, pm.force_N, pm.power_kW, pm.Rz_um,
           pm.mrr_cm3_per_min, std::nullopt};
  if (a.D) r.n = 1000.0 * pm.speed_m_per_min / (3.14159265358979323846 * *a.D);
  require_finite<Result>(who, r, kOutputs,
                         "--t, --T-life, --s-min, --s-max, --hardness, --D-mm and the material's "
                         "tables");
  if (!(pm.speed_m_per_min > 0.0))
    throw io::InputError(who + "the planned speed V_p comes out " + format_number(pm.speed_m_per_min) +
                         " m/min: --t, --T-life and --hardness are too far from the material's "
                         "tables");
  if (a.json) {
    nlohmann::json j;
    j["inputs"] = inputs_json<Args>(a, kInputs);
    j["inputs"]["material"] = mat->name;
    j["limit"] = limit_name(pm.limit);
    j["results"] = nlohmann::json::object();
    outputs_json<Result>(j, r, kOutputs, "si", "results");
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("Planned mode (seed 004's V_p, S_p) for %s at t_p = %g mm, T = %g min\n",
              mat->name.c_str(), *a.t, a.T);
  std::printf("  S_p is set by the %s\n", limit_name(pm.limit));
  for (const auto& o : kOutputs) print_shop_row(r, o);
  return 0;
}

void add(CLI::App& sub, Commands& out) {
  add_material_calculator<Args>(
      sub, out, kInputs,
      "Seed 004 and its setters: " + doc("system-e-adaptive.md") +
          "; materials: " + doc("materials-reference.md") + ".",
      "material in data/materials.toml (required): its tool-life table (Cv, m, xv, yv per feed "
      "range), Pz law and strength exponents",
      "print JSON (inputs, the limit that sets S_p, results)", &compute);
}

std::string reference() {
  return "Inputs (`--material NAME`, required, supplies the tool-life table, the Pz law and the "
         "strength exponents from data/materials.toml):\n\n" +
         inputs_markdown<Args>(kInputs) +
         "\nResults (`--json`: `results`, shop units; `limit` names what sets S_p):\n\n" +
         outputs_markdown<Result>(kOutputs);
}

std::vector<CalculatorInput> inputs() { return input_rows<Args>(kInputs); }

}  // namespace

const Calculator kPlannedMode{
    "planned-mode",
    "Seed 004's setters: planned feed S_p (the largest the force, power, roughness and feed limits "
    "allow) and speed V_p (the planned tool life at S_p, handbook tool-life table)",
    &add, &reference, &inputs};

}  // namespace lathectl::cli
