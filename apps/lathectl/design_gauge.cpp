// `lathectl design gauge`: seed 003's linearised vibro-contact gauging, (20)-(25)
// (design/vibro_gauge.hpp). Every input and output is one row below.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "calculator.hpp"
#include "cli.hpp"
#include "design_gauge.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/io/errors.hpp"

namespace lathectl::cli {
namespace {

using io::Range;

struct Args {  // shop units, as the flags; the initial values are the defaults
  double supply_V = 24.0, supply_Hz = 50.0, coil_turns = 1000.0, coil_ohm = 50.0, coil_H = 0.5;
  double force_coeff_N_per_Wb2 = 2.11e8;
  double probe_mass_g = 20.0;
  double probe_damping_N_s_per_m = 1.382;
  double probe_stiffness_N_per_mm = 9.554;
  double contact_stiffness_N_per_mm = 1000.0, contact_damping_N_s_per_m = 5.0;
  double generator_V_per_m_per_s = 50.0;
  double generator_ms = 0.2, filter_ms = 100.0, relay_ms = 20.0;
  double magnet_gap_mm = 0.0, pm_force_N = 0.0, pm_gap_mm = 0.0;
  double allowance_um = 250.0, removal_um_per_s = 20.0, target_um = 100.0;
  double noise_sigma_um = 2.0, noise_beta_per_s = 5.0;
  std::optional<double> tolerance_um;
  bool json = false;
};

// Ranges: what a vibro-contact gauge can be (probes of 10 mg to 10 kg, coils of 1 µH to 1 kH,
// supplies up to 10 kV and 10 kHz, times up to 10 s, allowances and sizes up to 10 mm): beyond
// them the results overflow or the full model's simulation runs for hours.
// 50 times the default's 40 000 (0.8 s at 20 µs): a few seconds at most for the whole range.
constexpr double kMaxStepsPerLevel = 2e6;
const Input<Args> kInputs[] = {
    {"--supply-V", {"supply_V", Range{0.0, 1e4, true, false}, "electromagnet supply amplitude V"}, "V", &Args::supply_V},
    {"--supply-Hz",
     {"supply_Hz", Range{0.0, 1e4, true, false}, "supply frequency ω/2π"},
     "Hz",
     &Args::supply_Hz,
     "(the probe runs at 2ω)"},
    {"--coil-turns", {"coil_turns", Range::closed(1, 1e6), "electromagnet coil turns W"}, "", &Args::coil_turns},
    {"--coil-ohm", {"coil_ohm", Range::closed(1e-3, 1e6), "coil resistance r"}, "Ω", &Args::coil_ohm},
    {"--coil-H", {"coil_H", Range::closed(1e-6, 1e3), "coil inductance L"}, "H", &Args::coil_H},
    {"--force-coeff",
     {"force_coeff_N_per_Wb2", Range::closed(1, 1e12), "magnet force coefficient a, F = a·Φ²"},
     "N/Wb²",
     &Args::force_coeff_N_per_Wb2},
    {"--probe-mass-g", {"probe_mass_g", Range::closed(0.01, 1e4), "probe mass M"}, "g", &Args::probe_mass_g},
    {"--probe-damping",
     {"probe_damping_N_s_per_m", Range::closed(0, 1e4), "probe damping h"},
     "N·s/m",
     &Args::probe_damping_N_s_per_m},
    {"--probe-stiffness-N-per-mm",
     {"probe_stiffness_N_per_mm", Range::closed(1e-3, 1e6), "probe spring stiffness k"},
     "N/mm",
     &Args::probe_stiffness_N_per_mm},
    {"--contact-stiffness-N-per-mm",
     {"contact_stiffness_N_per_mm", Range::closed(1e-3, 1e7), "probe-part contact stiffness k_c"},
     "N/mm",
     &Args::contact_stiffness_N_per_mm},
    {"--contact-damping",
     {"contact_damping_N_s_per_m", Range::closed(0, 1e5), "probe-part contact damping c_c"},
     "N·s/m",
     &Args::contact_damping_N_s_per_m},
    {"--generator",
     {"generator_V_per_m_per_s", Range::closed(1e-3, 1e6), "sensor-generator constant K_g"},
     "V per m/s",
     &Args::generator_V_per_m_per_s},
    {"--generator-ms",
     {"generator_ms", Range::closed(0, 1e4), "generator time constant T_g"},
     "ms",
     &Args::generator_ms},
    {"--filter-ms",
     {"filter_ms", Range{0.0, 1e4, true, false}, "smoothing filter time constant T_f"},
     "ms",
     &Args::filter_ms},
    {"--magnet-gap-mm",
     {"magnet_gap_mm", Range::closed(0, 100), "electromagnet air gap δ of (6) Φ = (L·i/W)·δ/(δ − z); 0: linear"},
     "mm",
     &Args::magnet_gap_mm},
    {"--pm-force-N",
     {"pm_force_N", Range::closed(0, 1e4), "permanent magnet's pull at rest F_M0, (9)-(10)"},
     "N",
     &Args::pm_force_N},
    {"--pm-gap-mm",
     {"pm_gap_mm", Range::closed(0, 100), "permanent magnet's gap b₂ of (11); 0: linear generator"},
     "mm",
     &Args::pm_gap_mm},
    {"--relay-ms", {"relay_ms", Range::closed(0, 1e4), "relay/command response time t_r"}, "ms", &Args::relay_ms},
    {"--allowance-um",
     {"allowance_um", Range{0.0, 1e4, true, false}, "controlled allowance at the start m_x"},
     "µm",
     &Args::allowance_um},
    {"--removal-um-per-s",
     {"removal_um_per_s", Range{0.0, 1e4, true, false}, "removal rate a"},
     "µm/s",
     &Args::removal_um_per_s},
    {"--target-um", {"target_um", Range::closed(0, 1e4), "final controlled size x_k"}, "µm", &Args::target_um},
    {"--noise-sigma-um",
     {"noise_sigma_um", Range::closed(0, 1e3), "disturbance σ = sqrt(D)"},
     "µm",
     &Args::noise_sigma_um},
    {"--noise-beta",
     {"noise_beta_per_s", Range::closed(0, 1e6), "disturbance correlation decay β, R = D·e^(−β|τ|)"},
     "1/s",
     &Args::noise_beta_per_s},
    {"--tolerance-um",
     {"tolerance_um", Range{0.0, 1e4, true, false}, "± size tolerance"},
     "µm",
     &Args::tolerance_um,
     "→ also Cp = 2·tol/(6·σ_x)"},
};

struct Result : design::GaugeResult {
  double sigma_y_V = 0.0;                                                // sqrt(D_y)
  double floor_V = 0.0, floor_start_m = 0.0, low_V = 0.0, high_V = 0.0;  // range.*
  bool in_range = false;     // S_th inside [low_V, high_V]
  std::optional<double> Cp;  // with a tolerance
};
const Output<Result> kOutputs[] = {
    {"free amplitude A0 (max allowance)", "A0_m", "m", "A0_um", "µm", 1e6,
     &Result::free_amplitude_m},
    {"static probe offset", "static_offset_m", "m", "static_offset_um", "µm", 1e6,
     &Result::static_offset_m},
    {"signal gain K", "K_V_per_m", "V/m", "K_mV_per_um", "mV/µm", 1e-3,
     &Result::signal_gain_V_per_m},
    {"intercept B0/q1 (20)", "intercept_m", "m", "intercept_um", "µm", 1e6, &Result::intercept_m},
    {"signal at target K·(A0 − x_k)", "S_target_V", "V", "S_target_V", "V", 1,
     &Result::signal_at_target_V},
    {"threshold S_th (23)", "S_th_V", "V", "S_th_V", "V", 1, &Result::threshold_V},
    {"end of cut t_k (22)", "t_k_s", "s", "t_k_s", "s", 1, &Result::end_time_s},
    {"signal noise D_y (25)", "D_y_V2", "V²", "D_y_V2", "V²", 1, &Result::noise_variance_V2},
    {"signal noise σ_y = sqrt(D_y)", "sigma_y_V", "V", "sigma_y_mV", "mV", 1e3, &Result::sigma_y_V},
    {"size scatter σ_x", "sigma_x_m", "m", "sigma_x_um", "µm", 1e6, &Result::size_sigma_m},
    {"full model: signal floor (bounce)", "S_floor_V", "V", "S_floor_V", "V", 1, &Result::floor_V},
    {"full model: floor from x", "floor_from_m", "m", "floor_from_um", "µm", 1e6,
     &Result::floor_start_m},
    {"safe S_th from (floor + margin)", "S_th_low_V", "V", "S_th_low_V", "V", 1, &Result::low_V},
    {"safe S_th up to (free − margin)", "S_th_high_V", "V", "S_th_high_V", "V", 1, &Result::high_V},
    {"safe range of targets ends at", "largest_target_m", "m", "largest_target_um", "µm", 1e6,
     &Result::largest_target_m},
    {"S_th in the safe range", "in_range", "", "in_range", "", 1, &Result::in_range},
    {"probe spread at trip (Poincaré)", "trip_spread_m", "m", "trip_spread_um", "µm", 1e6,
     &Result::trip_spread_m},
    {"probe regular (spread ≤ 3 % A0)", "regular", "", "regular", "", 1, &Result::regular},
    {"Cp = 2·tol/(6·σ_x)", "Cp", "", "Cp", "", 1, &Result::Cp},
};

// --force: compute even when the threshold lies outside the safe range; --filter: the filter's
// kind (flags that are not number rows).
bool force = false;
std::string filter_kind = "first_order";
// --calibration FILE.csv: the line measured on the transducer (design_gauge_calibration.cpp)
// instead of its physics, whose flags are then refused; `bound` says which flags were given.
std::string calibration_path;
std::shared_ptr<BoundInputs<Args>> bound;
// The transducer's physical flags (coil, probe, contact, magnets, generator): what a measured
// calibration replaces. --supply-Hz stays (the synchronous filter's window), as do the filter,
// the relay and the process.
const char* const kPhysical[] = {"--supply-V",      "--coil-turns",    "--coil-ohm",
                                 "--coil-H",        "--force-coeff",   "--probe-mass-g",
                                 "--probe-damping", "--probe-stiffness-N-per-mm",
                                 "--contact-stiffness-N-per-mm",       "--contact-damping",
                                 "--generator",     "--generator-ms",  "--magnet-gap-mm",
                                 "--pm-force-N",    "--pm-gap-mm"};

int from_calibration(const Args& a, const design::GaugeInput& in) {
  std::string given;
  for (const char* f : kPhysical)
    if (const auto* o = bound->option(f); o && o->count() > 0)
      given += (given.empty() ? "" : ", ") + std::string(f);
  if (!given.empty())
    throw io::InputError("design gauge: " + given + ": the transducer's physics, refused beside "
                         "--calibration (the measured curve holds them)");
  CalibrationRun run;
  run.path = calibration_path;
  run.in = in;
  run.tolerance_um = a.tolerance_um;
  run.json = a.json;
  run.force = force;
  run.inputs = inputs_json<Args>(a, kInputs);
  for (const char* f : kPhysical)
    for (const auto& row : kInputs)
      if (row.flag == f) run.inputs.erase(std::string(row.param.key));
  run.inputs["calibration"] = calibration_path;
  run.inputs["filter"] = filter_kind;
  if (force) run.inputs["force"] = true;
  return gauge_from_calibration(run);
}

design::GaugeInput gauge_input(const Args& a) {
  design::GaugeInput in;
  in.supply_V = a.supply_V;
  in.supply_Hz = a.supply_Hz;
  in.coil_turns = a.coil_turns;
  in.coil_resistance_ohm = a.coil_ohm;
  in.coil_inductance_H = a.coil_H;
  in.force_coefficient_N_per_Wb2 = a.force_coeff_N_per_Wb2;
  in.probe_mass_kg = a.probe_mass_g * 1e-3;
  in.probe_damping_N_s_per_m = a.probe_damping_N_s_per_m;
  in.probe_stiffness_N_per_m = a.probe_stiffness_N_per_mm * 1e3;
  in.contact_stiffness_N_per_m = a.contact_stiffness_N_per_mm * 1e3;
  in.contact_damping_N_s_per_m = a.contact_damping_N_s_per_m;
  in.generator_V_per_m_per_s = a.generator_V_per_m_per_s;
  in.generator_time_constant_s = a.generator_ms * 1e-3;
  in.filter_time_constant_s = a.filter_ms * 1e-3;
  in.relay_response_s = a.relay_ms * 1e-3;
  in.magnet_gap_m = a.magnet_gap_mm * 1e-3;
  in.pm_force_N = a.pm_force_N;
  in.pm_gap_m = a.pm_gap_mm * 1e-3;
  using F = sensors::VibroContactGauge::Params::Filter;
  in.filter = filter_kind == "second_order"  ? F::SecondOrder
              : filter_kind == "synchronous" ? F::Synchronous
                                             : F::FirstOrder;
  in.allowance_m = a.allowance_um * 1e-6;
  in.removal_m_per_s = a.removal_um_per_s * 1e-6;
  in.target_m = a.target_um * 1e-6;
  in.noise_variance_m2 = a.noise_sigma_um * a.noise_sigma_um * 1e-12;
  in.noise_beta_per_s = a.noise_beta_per_s;
  return in;
}

// The full model is simulated at every level of the range and the trip (~60 levels), each for
// the settling time 8·T_f at a step that resolves the contact and the supply: count the steps
// first, and refuse at once what would run for minutes (--filter-ms 1e6 did, then failed).
void check_full_model_cost(const design::GaugeInput& in, const std::string& who) {
  char buf[512];
  sensors::VibroContactGauge::Params p;
  p.supply_Hz = in.supply_Hz;
  p.contact_stiffness_N_per_m = in.contact_stiffness_N_per_m;
  p.probe_mass_kg = in.probe_mass_kg;
  p.filter_time_constant_s = in.filter_time_constant_s;
  const double step = design::full_model_step(p), settle = design::full_model_settle(p);
  const double steps = settle / step;
  if (!(steps <= kMaxStepsPerLevel)) {
    const bool slow_filter = settle > 0.8;
    std::snprintf(buf, sizeof buf,
                  "%s: the full model would simulate %.3g steps per signal level (settling "
                  "%.3g s at a step of %.3g s), over %.3g: %s",
                  slow_filter ? "--filter-ms" : "--contact-stiffness-N-per-mm, --probe-mass-g, "
                                                "--supply-Hz",
                  steps, settle, step, kMaxStepsPerLevel,
                  slow_filter ? ("the settling time is 8·T_f; at this step a filter of at "
                                 "most " + format_number(kMaxStepsPerLevel * step / 8.0 * 1e3) +
                                 " ms").c_str()
                              : "the step resolves the contact frequency sqrt(k_c/M) and the "
                                "supply; a softer contact, a heavier probe or a lower supply "
                                "frequency");
    throw io::InputError(who + buf);
  }
}

// The gauge designed (design::gauge), refused without a usable threshold, or (without --force)
// with one outside the safe range.
Result gauge_result(const design::GaugeInput& in, const Args& a, const std::string& who) {
  char buf[512];
  Result r;
  try {
    static_cast<design::GaugeResult&>(r) = design::gauge(in);
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    const char* flags = m.find("gap") != std::string::npos ? " (--magnet-gap-mm, --pm-gap-mm)"
                        : m.find("noise") != std::string::npos ? " (--noise-sigma-um, --noise-beta)"
                                                               : "";
    throw io::InputError(who + m + flags);
  }
  if (!(r.threshold_V > 0.0)) {
    std::snprintf(
        buf, sizeof buf,
        "no usable threshold: S_th = %.4g V <= 0, since x_k + a·(T_f + t_r) = %.4g µm "
        "reaches the free amplitude A0 = %.4g µm: lower --target-um, --removal-um-per-s, "
        "--filter-ms or --relay-ms, or raise A0 (--supply-V, --coil-*, --force-coeff, --probe-*)",
        r.threshold_V,
        (in.target_m + in.removal_m_per_s * (in.filter_time_constant_s + in.relay_response_s)) *
            1e6,
        r.free_amplitude_m * 1e6);
    throw io::InputError(who + buf);
  }
  r.floor_V = r.range.floor_V;
  r.floor_start_m = r.range.floor_start_m;
  r.low_V = r.range.low_V;
  r.high_V = r.range.high_V;
  r.in_range = r.range.contains(r.threshold_V);
  if (!r.in_range && !force) {
    const bool below = r.threshold_V < r.low_V;
    std::snprintf(buf, sizeof buf,
                  "--target-um %g: threshold S_th (23) = %.3f V lies %s %.3f V (%s %.3f V, margin "
                  "ripple %.3f V + 4σ noise %.3f V): the relay would never trip; the safe range "
                  "ends at --target-um %.1f (--force to compute anyway)",
                  a.target_um, r.threshold_V, below ? "below" : "above", below ? r.low_V : r.high_V,
                  below ? "the full model's bounce floor" : "the free signal",
                  below ? r.floor_V : r.range.free_V, r.range.ripple_V, 4.0 * r.range.noise_sigma_V,
                  r.largest_target_m * 1e6);
    throw io::InputError(who + buf);
  }
  return r;
}

int compute(const Args& a) {
  const std::string who = "design gauge: ";
  const design::GaugeInput in = gauge_input(a);
  if (!(a.target_um < a.allowance_um)) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "--target-um (%g) must be below --allowance-um (%g): nothing to remove",
                  a.target_um, a.allowance_um);
    throw io::InputError(who + buf);
  }
  if (!calibration_path.empty()) return from_calibration(a, in);
  check_full_model_cost(in, who);
  Result r = gauge_result(in, a, who);
  r.sigma_y_V = std::sqrt(r.noise_variance_V2);
  require_finite<Result>(who, r, kOutputs,
                         "the transducer's (--supply-V, --coil-*, --force-coeff, --probe-*, "
                         "--generator) and the cut's (--allowance-um, --removal-um-per-s)");
  if (in.allowance_m > r.free_amplitude_m)
    std::cerr << "note: allowance " << a.allowance_um
              << " µm exceeds the largest measurable A0 = " << r.free_amplitude_m * 1e6
              << " µm; the gauge reads nothing until x < A0\n";
  if (!r.regular)
    std::cerr << "note: the probe is not regular at the trip point (Poincaré spread "
              << r.trip_spread_m * 1e6 << " µm > 3 % of A0): its period-doubled impacts make the "
              << "trip time erratic; damp the contact (ζ_c ≥ 0.35), soften it, or put the "
              << "resonance at or below 2ω\n";
  if (a.tolerance_um)  // unbounded without noise (JSON null)
    r.Cp = r.size_sigma_m > 0.0 ? 2.0 * *a.tolerance_um * 1e-6 / (6.0 * r.size_sigma_m)
                                : std::numeric_limits<double>::infinity();
  // --filter and --force in the inputs too: what changes the result is in them, so that they
  // can be given back (lathectl.design.gauge(**result["inputs"])).
  nlohmann::json more = {{"filter", filter_kind}};
  if (force) more["force"] = true;
  return print_result<Args, Result>(
      a, kInputs, r, kOutputs,
      "Vibro-contact in-process gauge (seed 003, linearised (20)-(25); range: full model)", more);
}

void add(CLI::App& sub, Commands& out) {
  // The flags' defaults again for each command line parsed: the Python module parses many in
  // one process (lathectl.design.gauge), and a --force must not outlive its call.
  force = false;
  filter_kind = "first_order";
  calibration_path.clear();
  bound = add_calculator<Args>(
      sub, out, kInputs, "Seed 003 and its formulas (20)-(25): " + doc("system-d-gauging.md") + ".",
      &compute);
  sub.add_option("--calibration", calibration_path,
                 "design from the transducer's measured curve, a CSV allowance_um,voltage_V, "
                 "instead of its coil and probe (whose flags it refuses)");
  sub.add_option("--filter", filter_kind,
                 "filter after the rectifier: first_order (the seed's), second_order, synchronous")
      ->check(CLI::IsMember({"first_order", "second_order", "synchronous"}))
      ->capture_default_str();
  sub.add_flag("--force", force,
               "compute even when S_th lies outside the signal range the full model reaches");
}

std::string reference() {
  return calculator_reference<Args, Result>(kInputs, kOutputs) +
         "\nResults with `--calibration FILE.csv` (the transducer's flags refused):\n\n" +
         calibration_outputs_markdown();
}

std::vector<CalculatorInput> inputs() { return input_rows<Args>(kInputs); }

}  // namespace

const Calculator kGauge{
    "gauge",
    "Seed 003: vibro-contact in-process gauge — free amplitude A0, gain K, threshold S_th (23), "
    "end time t_k (22), filtered noise D_y (25), size scatter σ_x and Cp",
    &add, &reference, &inputs};

}  // namespace lathectl::cli
