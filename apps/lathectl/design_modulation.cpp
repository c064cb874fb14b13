// `lathectl design modulation`: seed 001's CNC module as a calculator — the modulated-feed plan
// (ω_m, A_P, S_min, ΔS, Δl, n_s) for a measured vibration a0 at ω_d on a slender part between
// centres. The plan is control::ModulatedFeedController::plan_for, the formula the machine runs
// (docs/system-b-chatter.md); m_d is the part's first modal mass at the tool
// (dynamics::beam_mode_at) unless given. Every input and output is one row below.
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/control/modulated_feed.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/io/errors.hpp"

namespace lathectl::cli {
namespace {

using io::Range;
using Opt = std::optional<double>;

struct Args {  // shop units, as the flags; the initial values are the defaults
  double a0_um = 6.0, fd_Hz = 227.0;
  double D_mm = 40.0, L_mm = 800.0;
  Opt x_mm, m_d_kg;
  double E_GPa = 210.0, rho = 7850.0;
  double power_kW = 0.38, s_mm_per_rev = 0.14, n_rpm = 820.0;
  double r = 0.3, e = 0.51;
  double fm_Hz = 2.0, bandwidth_Hz = 30.0, n_s = 5.0, c = 1.41;
  double s_min_fraction = 0.2, s_max_fraction = 2.0, resolution_um = 1.0, desync = 0.0;
  bool json = false;
};

const Range kPos = Range::positive();
const Input<Args> kInputs[] = {
    {"--a0-um", {"a0_um", Range{0.0, 1e5, true, true}, "vibration amplitude a0 (ADC 19)"}, "µm",
     &Args::a0_um},
    {"--fd-Hz", {"fd_Hz", Range{0.0, 1e5, true, true}, "vibration frequency ω_d/2π (detector 20)"},
     "Hz", &Args::fd_Hz},
    {"--D-mm", {"D_mm", Range::closed(1, 2000), "part diameter D"}, "mm", &Args::D_mm},
    {"--L-mm", {"L_mm", Range::closed(10, 20000), "part length between centres L"}, "mm",
     &Args::L_mm},
    {"--x-mm", {"x_mm", kPos, "tool position from the left centre"}, "mm", &Args::x_mm,
     "(default L/2)"},
    {"--m-d-kg", {"m_d_kg", Range{0.0, 1e6, true, false}, "m_d, instead of the first modal mass"},
     "kg", &Args::m_d_kg, "(the seed: the part's mass)"},
    {"--E-GPa", {"E_GPa", Range::closed(1, 1000), "Young's modulus E"}, "GPa", &Args::E_GPa},
    {"--density", {"density_kg_per_m3", Range::closed(100, 30000), "density ρ"}, "kg/m³",
     &Args::rho},
    {"--power-kW", {"power_kW", Range{0.0, 1e4, true, false}, "cutting power N_c (adder 14)"},
     "kW", &Args::power_kW},
    {"--s", {"s_mm_per_rev", Range{0.0, 100, true, false}, "programmed feed s"}, "mm/rev",
     &Args::s_mm_per_rev},
    {"--n", {"n_rpm", Range{0.0, 1e5, true, false}, "spindle speed n"}, "rpm", &Args::n_rpm},
    {"--radial-ratio", {"radial_force_ratio", Range{0.0, 10, true, false},
                        "r: force along the vibration / tangential force"}, "", &Args::r},
    {"--exponent", {"force_feed_exponent", Range{0.0, 1.5, true, true}, "e in F ∝ S^e (1 − m)"},
     "", &Args::e},
    {"--fm-Hz", {"modulation_frequency_Hz", Range{0.0, 1e4, true, false}, "wanted ω_m/2π"}, "Hz",
     &Args::fm_Hz},
    {"--bandwidth-Hz", {"drive_bandwidth_Hz", Range{0.0, 1e4, true, false},
                        "feed drive bandwidth (ω_m below a quarter of it)"}, "Hz",
     &Args::bandwidth_Hz},
    {"--n-s", {"n_s", Range::closed(1, 1000), "increments n_s from S_min to S_max"}, "",
     &Args::n_s},
    {"--c", {"coefficient", Range{0.0, 100, true, false},
             "c in A_P ≥ c·a0·m_d·|ω_d² − ω_m²| (1.41 multiply; 0.709 the seed read dividing)"},
     "", &Args::c},
    {"--s-min-fraction", {"s_min_fraction", Range{0.0, 1.0, true, true}, "S_min ≥ this·S_p"}, "",
     &Args::s_min_fraction},
    {"--s-max-fraction", {"s_max_fraction", Range{1.0, 100, true, false}, "S_max ≤ this·S_p"}, "",
     &Args::s_max_fraction},
    {"--resolution-um", {"resolution_um", Range{0.0, 1e4, true, false},
                         "the control's resolution (Δl a multiple of it)"}, "µm",
     &Args::resolution_um},
    {"--desync", {"desync_fraction", Range::closed(0, 100),
                  "> 0: Δl long enough for the turrets' offset to swing this·s"}, "",
     &Args::desync},
};

struct Result {
  double m_d = 0, f_n = 0, S_p = 0, V = 0, F = 0;
  double f_m = 0, required = 0, planned = 0, B = 0;
  double S_min = 0, dS = 0, dl = 0, n_s = 0, S_max = 0, mean = 0, cycle = 0, swing = 0;
  bool limited = false;
};
const Output<Result> kOutputs[] = {
    {"m_d (modal mass at the tool)", "m_d_kg", "kg", "m_d_kg", "kg", 1,
     &Result::m_d},
    {"first natural frequency at the tool", "f_n_Hz", "Hz", "f_n_Hz", "Hz", 1, &Result::f_n},
    {"programmed feed S_p = s·n", "S_p_m_per_s", "m/s", "S_p_mm_per_min", "mm/min", 6e4,
     &Result::S_p},
    {"cutting speed V = π·D·n", "V_m_per_s", "m/s", "V_m_per_min", "m/min", 60, &Result::V},
    {"force F = r·N_c/V", "F_N", "N", "F_N", "N", 1, &Result::F},
    {"modulation frequency ω_m/2π", "f_m_Hz", "Hz", "f_m_Hz", "Hz", 1, &Result::f_m},
    {"A_P required, c·a0·m_d·|ω_d²−ω_m²|", "A_P_required_N", "N", "A_P_required_N", "N", 1,
     &Result::required},
    {"A_P planned", "A_P_planned_N", "N", "A_P_planned_N",
     "N", 1, &Result::planned},
    {"forced amplitude B", "B_m", "m", "B_um", "µm", 1e6, &Result::B},
    {"S_min", "S_min_m_per_s", "m/s", "S_min_mm_per_min", "mm/min", 6e4, &Result::S_min},
    {"ΔS", "dS_m_per_s", "m/s", "dS_mm_per_min", "mm/min", 6e4, &Result::dS},
    {"Δl", "dl_m", "m", "dl_mm", "mm", 1e3, &Result::dl},
    {"n_s", "n_s", "", "n_s", "", 1, &Result::n_s},
    {"S_max = S_min + n_s·ΔS", "S_max_m_per_s", "m/s", "S_max_mm_per_min", "mm/min", 6e4,
     &Result::S_max},
    {"time-mean feed", "mean_feed_m_per_s", "m/s",
     "mean_feed_mm_per_min", "mm/min", 6e4, &Result::mean},
    {"cycle length 2·n_s·Δl", "cycle_m", "m", "cycle_mm", "mm", 1e3, &Result::cycle},
    {"offset swing vs a turret at S_p", "offset_swing_m", "m", "offset_swing_um", "µm", 1e6,
     &Result::swing},
    {"limited (A_P short at the limits)", "limited", "", "limited", "", 1,
     &Result::limited},
};

int compute(const Args& a) {
  const std::string who = "design modulation: ";
  constexpr double kPi = std::numbers::pi;
  const double x_mm = a.x_mm.value_or(0.5 * a.L_mm);
  if (!(x_mm > 0.0 && x_mm < a.L_mm))
    throw io::InputError(who + "--x-mm must lie between the centres: 0 < x < L = " +
                         format_number(a.L_mm) + " mm");
  if (std::abs(a.n_s - std::round(a.n_s)) > 1e-9)
    throw io::InputError(who + "--n-s must be a whole number");
  dynamics::BeamPart part;
  part.length_m = a.L_mm * 1e-3;
  part.diameter_m = a.D_mm * 1e-3;
  part.youngs_modulus_Pa = a.E_GPa * 1e9;
  part.density_kg_per_m3 = a.rho;
  const auto mode = dynamics::beam_mode_at(part, x_mm * 1e-3, 1);
  Result r;
  r.f_n = mode.mode.natural_frequency_Hz;
  r.m_d = a.m_d_kg.value_or(mode.mass_kg);
  control::ModulatedFeedController::Params p;
  p.coefficient = a.c;
  p.part_mass_kg = r.m_d;
  p.radial_force_ratio = a.r;
  p.force_feed_exponent = a.e;
  p.modulation_frequency_Hz = a.fm_Hz;
  p.drive_bandwidth_Hz = a.bandwidth_Hz;
  p.n_s = static_cast<int>(std::lround(a.n_s));
  p.resolution_mm = a.resolution_um * 1e-3;
  p.s_min_fraction = a.s_min_fraction;
  p.s_max_fraction = a.s_max_fraction;
  p.desync_fraction = a.desync;
  control::ModulatedFeedController m;
  try {
    m.configure(p);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(who + e.what());
  }
  const double s_p = a.s_mm_per_rev * a.n_rpm;        // mm/min
  const double v = kPi * a.D_mm * 1e-3 * a.n_rpm;     // m/min
  const double wd = 2.0 * kPi * a.fd_Hz;
  double wm = 0.0;
  const control::ModulationPlan plan =
      m.plan_for(a.a0_um * 1e-6, wd, a.power_kW * 1e3, v, s_p, a.n_rpm, wm, r.required, r.planned,
                 r.limited);
  r.S_p = s_p / 6e4;
  r.V = v / 60.0;
  r.F = a.r * a.power_kW * 1e3 / r.V;
  r.f_m = wm / (2.0 * kPi);
  r.B = r.planned / (r.m_d * std::abs(wd * wd - wm * wm));
  r.S_min = plan.s_min_mm_per_min / 6e4;
  r.dS = plan.ds_mm_per_min / 6e4;
  r.dl = plan.dl_mm * 1e-3;
  r.n_s = plan.n_s;
  r.S_max = plan.s_max_mm_per_min() / 6e4;
  r.mean = plan.time_mean_feed() / 6e4;
  r.cycle = plan.cycle_length_mm() * 1e-3;
  r.swing = plan.offset_swing_mm(s_p) * 1e-3;
  require_finite<Result>(who, r, kOutputs, "--a0-um, --fd-Hz, --power-kW, --s, --n and the part");
  return print_result<Args, Result>(
      a, kInputs, r, kOutputs, "Modulated-feed plan (seed 001's CNC module, system B)");
}

void add(CLI::App& sub, Commands& out) {
  add_calculator<Args>(sub, out, kInputs,
                       "Seed 001's module and its quenching condition: " +
                           doc("system-b-chatter.md") + ".",
                       &compute);
}

std::string reference() {
  return calculator_reference<Args, Result>(kInputs, kOutputs);
}

std::vector<CalculatorInput> inputs() { return input_rows<Args>(kInputs); }

}  // namespace

const Calculator kModulation{
    "modulation",
    "Seed 001's CNC module: the modulated-feed plan (ω_m, A_P, S_min, ΔS, Δl, n_s) that quenches "
    "a vibration a0 at ω_d on a slender part between centres, the time-mean feed kept",
    &add, &reference, &inputs};

}  // namespace lathectl::cli
