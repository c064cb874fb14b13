// `lathectl design pulse-regulator`: seed 000's pulsed flow regulator, formulas (1)-(7)
// (design/pulse_regulator.hpp). Every input and output is one row below.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/design/pulse_regulator.hpp"
#include "lathectl/io/errors.hpp"

namespace lathectl::cli {
namespace {

using io::Range;

struct Args {  // shop units, as the flags; the initial values are the defaults
  double d_mm = 8, h_mm = 0.04, dp_MPa = 0.5, rho_kg_per_m3 = 870, mu = 0.65, dt_ms = 10;
  std::optional<double> T_ms, f_Hz;
  double F_cm2 = 20, leak_cm3_per_min_per_MPa = 0, Py_N = 0, dPy_N = 0;
  bool json = false;
};

// Ranges: what a hydraulic feed regulator can be (and what keeps every result finite): a spool of
// 1 µm to 1 m, slots of 0.1 µm to 100 mm, 1 kPa to 1000 MPa, liquids of 100 to 20 000 kg/m³,
// pulses and periods of 1 µs to 1000 s, pistons of 1 mm² to 10 m², forces up to 10 MN.
const Input<Args> kInputs[] = {
    {"--d-mm", {"d_mm", Range::closed(1e-3, 1e3), "spool diameter d"}, "mm", &Args::d_mm},
    {"--h-mm", {"h_mm", Range::closed(1e-4, 100), "slot opening h"}, "mm", &Args::h_mm},
    {"--dp-MPa",
     {"dp_MPa", Range::closed(1e-3, 1e3), "pressure drop Δp across the regulator"},
     "MPa",
     &Args::dp_MPa},
    {"--rho", {"rho_kg_per_m3", Range::closed(100, 2e4), "oil density ρ"}, "kg/m³", &Args::rho_kg_per_m3},
    {"--mu", {"mu", Range{0.0, 1.0, true, false}, "discharge coefficient μ"}, "", &Args::mu},
    {"--dt-ms", {"dt_ms", Range::closed(1e-3, 1e6), "pulse width Δt"}, "ms", &Args::dt_ms},
    {"--T-ms", {"T_ms", Range::closed(1e-3, 1e6), "pulse period T"}, "ms", &Args::T_ms},
    {"--f-Hz",
     {"f_Hz", Range::closed(1e-3, 1e6), "pulse frequency f"},
     "Hz",
     &Args::f_Hz,
     "(instead of T)"},
    {"--F-cm2", {"F_cm2", Range::closed(1e-2, 1e5), "effective piston area F"}, "cm²", &Args::F_cm2},
    {"--leak",
     {"leak_cm3_per_min_per_MPa", Range::closed(0, 1e6), "leakage K_leak"},
     "cm³/min per MPa",
     &Args::leak_cm3_per_min_per_MPa},
    {"--Py", {"Py_N", Range::closed(-1e7, 1e7), "radial cutting force Py"}, "N", &Args::Py_N},
    {"--dPy", {"dPy_N", Range::closed(-1e7, 1e7), "force change ΔPy"}, "N", &Args::dPy_N},
};

using R = design::PulseRegulatorResult;
const Output<R> kOutputs[] = {
    {"mean flow Q (1)", "Q_m3_per_s", "m³/s", "Q_cm3_per_min", "cm³/min", 6e7, &R::flow_m3_per_s},
    {"AIM gain Ka (2)", "Ka_m2_per_s", "m²/s", "Ka_cm3_per_min_per_mm", "cm³/min per mm", 6e4,
     &R::ka_m2_per_s},
    {"FIM gain Kf (6)", "Kf_m3", "m³", "Kf_cm3_per_min_per_Hz", "cm³/min per Hz", 6e7, &R::kf_m3},
    {"feed without leakage Q/F", "S_no_leak_m_per_s", "m/s", "S_no_leak_mm_per_min", "mm/min", 6e4,
     &R::feed_no_leak_m_per_s},
    {"leakage K_leak·Py/F", "leak_m3_per_s", "m³/s", "leak_cm3_per_min", "cm³/min", 6e7,
     &R::leak_m3_per_s},
    {"feed S (3)", "S_m_per_s", "m/s", "S_mm_per_min", "mm/min", 6e4, &R::feed_m_per_s},
    {"slot correction Δh (4)", "dh_m", "m", "dh_um", "µm", 1e6, &R::slot_change_m},
    {"frequency correction Δf", "df_Hz", "Hz", "df_Hz", "Hz", 1, &R::frequency_change_Hz},
    {"duty Δt/T", "duty", "", "duty_pct", "%", 100, &R::duty},
    {"frequency f", "f_Hz", "Hz", "", "Hz", 1, &R::frequency_Hz},
};

int compute(const Args& a) {
  const std::string who = "design pulse-regulator: ";
  if (!a.T_ms && !a.f_Hz) throw io::InputError(who + "give --T-ms or --f-Hz");
  const double period_ms = a.T_ms ? *a.T_ms : 1e3 / *a.f_Hz;
  if (a.dt_ms > period_ms) {
    char buf[200];
    if (a.T_ms)
      std::snprintf(buf, sizeof buf, "--dt-ms %g exceeds the period --T-ms %g: a pulse is open "
                    "for at most its whole period", a.dt_ms, *a.T_ms);
    else
      std::snprintf(buf, sizeof buf, "--dt-ms %g exceeds the period 1/--f-Hz = %g ms: a pulse is "
                    "open for at most its whole period (lower --f-Hz or --dt-ms)", a.dt_ms,
                    period_ms);
    throw io::InputError(who + buf);
  }
  design::PulseRegulatorInput in;
  in.spool_diameter_m = a.d_mm * 1e-3;
  in.slot_m = a.h_mm * 1e-3;
  in.pressure_drop_Pa = a.dp_MPa * 1e6;
  in.density_kg_per_m3 = a.rho_kg_per_m3;
  in.discharge_coefficient = a.mu;
  in.pulse_width_s = a.dt_ms * 1e-3;
  in.period_s = a.T_ms ? *a.T_ms * 1e-3 : 1.0 / *a.f_Hz;
  in.piston_area_m2 = a.F_cm2 * 1e-4;
  in.leak_m3_per_s_Pa = a.leak_cm3_per_min_per_MPa * 1e-6 / 60.0 / 1e6;
  in.force_N = a.Py_N;
  in.force_change_N = a.dPy_N;
  R r;
  try {
    r = design::pulse_regulator(in);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(who + e.what());
  }
  require_finite<R>(who, r, kOutputs, "--d-mm, --h-mm, --dp-MPa, --dt-ms, --F-cm2, --leak, --Py, --dPy");
  return print_result<Args, R>(a, kInputs, r, kOutputs, "Pulsed flow regulator (seed 000)");
}

void add(CLI::App& sub, Commands& out) {
  auto bound = add_calculator<Args>(
      sub, out, kInputs,
      "Seed 000 and its formulas (1)-(7): " + doc("system-a-pulse-feed.md") + ".", &compute);
  bound->option("--T-ms")->excludes(bound->option("--f-Hz"));
}

std::string reference() {
  return calculator_reference<Args, R>(kInputs, kOutputs);
}

std::vector<CalculatorInput> inputs() { return input_rows<Args>(kInputs); }

}  // namespace

const Calculator kPulseRegulator{
    "pulse-regulator",
    "Seed 000: Q (1), Ka (2), S (3), Δh (4), Kf (6), Δf and duty of a pulsed flow regulator", &add,
    &reference, &inputs};

}  // namespace lathectl::cli
