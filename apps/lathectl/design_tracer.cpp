// `lathectl design tracer`: seed 002's linearised one-coordinate hydraulic tracer slide, (8)-(9),
// its profile errors on a cone (12)-(13) and its static characteristics (Fig. 1, --characteristics
// FILE.csv) (hydraulics/tracer.hpp). Every number input and output is one row below.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/hydraulics/tracer.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"

namespace lathectl::cli {
namespace {

using io::Range;

struct Args {  // shop units, as the flags; the initial values are the defaults
  double E0_N_per_mm = 2000.0, C0_per_s = 20.0, M_kg = 100.0, i = 3.0, P0_N = 500.0;
  double beta_deg = 45.0, alpha_deg = 30.0, s_mm_per_rev = 0.3, n_rpm = 600.0;
  bool json = false;
};

const Range kPos = Range::positive();
const Input<Args> kInputs[] = {
    {"--E0",
     {"E0_N_per_mm", kPos, "stiffness E0 = ∂P/∂h"},
     "N per mm of spool opening",
     &Args::E0_N_per_mm},
    {"--C0", {"C0_per_s", kPos, "velocity gain C0 = ∂V/∂h"}, "1/s", &Args::C0_per_s},
    {"--M", {"M_kg", kPos, "reduced moving mass M"}, "kg", &Args::M_kg},
    {"--i", {"i", kPos, "lever ratio i (spool opening per stylus deflection)"}, "", &Args::i},
    {"--P0", {"P0_N", Range::non_negative(), "cutting + dry friction force P0"}, "N", &Args::P0_N},
    {"--beta-deg",
     {"beta_deg", Range{0.0, 90.0, true, false}, "guide inclination β to the axis"},
     "deg",
     &Args::beta_deg},
    {"--alpha-deg",
     {"alpha_deg", Range{-1e300, 90.0, false, false}, "template cone angle α"},
     "deg",
     &Args::alpha_deg,
     "(≤ 90: a template y(x))"},
    {"--s", {"s_mm_per_rev", kPos, "feed s"}, "mm/rev", &Args::s_mm_per_rev},
    {"--n", {"n_rpm", kPos, "spindle speed n"}, "rpm", &Args::n_rpm},
};

struct Result {
  double v_pr = 0, v_t = 0, h_cone = 0, q_ss = 0, q_static = 0, q_dynamic = 0;
  std::optional<double> dx, dy;  // (12), (13): none on a cylinder (α = 0), a shoulder (α = 90°)
  double zeta = 0, omega_n = 0, f_n = 0, peak = 0, settling = 0;
  bool aperiodic = false;
};
const Output<Result> kOutputs[] = {
    {"carriage feed V_pr = s·n/60", "V_pr_m_per_s", "m/s", "V_pr_mm_per_min", "mm/min", 6e4,
     &Result::v_pr},
    {"slide rate v_T on the cone", "v_T_m_per_s", "m/s", "v_T_mm_per_min", "mm/min", 6e4,
     &Result::v_t},
    {"spool opening on the cone (9) h", "h_cone_m", "m", "h_cone_um", "µm", 1e6,
     &Result::h_cone},
    {"steady lag q_ss (along slide)", "q_ss_m", "m", "q_ss_um", "µm", 1e6, &Result::q_ss},
    {"  static part P0/(E0·i)", "q_static_m", "m", "q_static_um", "µm", 1e6, &Result::q_static},
    {"  dynamic part v_T/(C0·i)", "q_dynamic_m", "m", "q_dynamic_um", "µm", 1e6,
     &Result::q_dynamic},
    {"(12) δx at equal y = q·sin(α+β)/sin α", "dx_m", "m", "dx_um", "µm", 1e6, &Result::dx},
    {"(13) δy at equal x = −q·sin(α+β)/cos α", "dy_m", "m", "dy_um", "µm", 1e6, &Result::dy},
    {"damping ratio ζ", "zeta", "", "zeta", "", 1, &Result::zeta},
    {"natural frequency ω_n", "omega_n_rad_per_s", "rad/s", "", "rad/s", 1, &Result::omega_n},
    {"natural frequency ω_n/2π", "f_n_Hz", "Hz", "f_n_Hz", "Hz", 1, &Result::f_n},
    {"aperiodic (ζ ≥ 1)", "aperiodic", "", "aperiodic", "", 1, &Result::aperiodic},
    {"peak dynamic lag, cylinder→cone", "transient_peak_lag_m", "m", "transient_peak_lag_um", "µm",
     1e6, &Result::peak},
    {"settling time (2 %)", "settling_time_s", "s", "settling_time_ms", "ms", 1e3,
     &Result::settling},
};

// --characteristics FILE.csv (a flag that is not a number row): the seed's Fig. 1, the static
// characteristics of (9) as the linearisation draws them.
std::string characteristics_path;

// Fig. 1a: P = E0·(h − V_k/C0) at V_k = 0 and at the cone's v_T; Fig. 1b: V_k = C0·(h − P/E0) at
// P = 0 and at P0; each over the spool opening h = 0 … 2·h_cone in 20 steps (h_cone = P0/E0 +
// v_T/C0, the opening on the cone: the operating point lies mid-curve).
std::string characteristics_csv(const hydraulics::TracerLinear& t, double v_t) {
  const double h_max = 2.0 * t.static_opening_m(t.P0_N, v_t);
  std::string out = "figure,held,held_value,h_mm,P_N,V_k_mm_per_s\n";
  char buf[160];
  auto row = [&](const char* fig, const char* held, double held_value, double h, double P,
                 double V) {
    std::snprintf(buf, sizeof buf, "%s,%s,%.10g,%.10g,%.10g,%.10g\n", fig, held, held_value,
                  h * 1e3, P, V * 1e3);
    out += buf;
  };
  for (const double V : {0.0, v_t})
    for (int k = 0; k <= 20; ++k) {
      const double h = h_max * k / 20.0;
      row("1a", "V_k_mm_per_s", V * 1e3, h, t.E0_N_per_m * (h - V / t.C0_per_s), V);
    }
  for (const double P : {0.0, t.P0_N})
    for (int k = 0; k <= 20; ++k) {
      const double h = h_max * k / 20.0;
      row("1b", "P_N", P, h, P, t.C0_per_s * (h - P / t.E0_N_per_m));
    }
  return out;
}

int compute(const Args& a) {
  const std::string who = "design tracer: ";
  constexpr double kPi = 3.14159265358979323846, kDeg = kPi / 180.0;
  if (!(a.alpha_deg + a.beta_deg < 180.0) || !(a.alpha_deg > -a.beta_deg)) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the slide cannot follow this cone: need -β < α < 180° - β, got α = %g°, "
                  "β = %g°",
                  a.alpha_deg, a.beta_deg);
    throw io::InputError(who + buf);
  }
  hydraulics::TracerLinear t;
  t.E0_N_per_m = a.E0_N_per_mm * 1e3;
  t.C0_per_s = a.C0_per_s;
  t.mass_kg = a.M_kg;
  t.lever_ratio = a.i;
  t.P0_N = a.P0_N;
  const double al = a.alpha_deg * kDeg, be = a.beta_deg * kDeg;
  Result r;
  r.v_pr = a.s_mm_per_rev * a.n_rpm / 60.0 * 1e-3;    // m/s
  r.v_t = r.v_pr * std::sin(al) / std::sin(al + be);  // m/s along the slide
  r.q_ss = t.steady_lag_m(r.v_t);                     // m along the slide
  r.h_cone = t.static_opening_m(t.P0_N, r.v_t);  // = i·q_ss
  r.q_static = t.static_offset_m();
  r.q_dynamic = r.q_ss - r.q_static;  // v_T/(C0·i)
  // (12)-(13) of the dynamic lag: the static one, P0/(E0·i), is on the first cylinder already,
  // where the tool is set to size (as rig C sets it).
  const auto err = hydraulics::cone_profile_error(r.q_dynamic, al, be);
  if (std::isfinite(err.dx_m)) r.dx = err.dx_m;
  if (std::isfinite(err.dy_m)) r.dy = err.dy_m;
  r.zeta = t.zeta();
  r.omega_n = t.omega_n();
  r.f_n = r.omega_n / (2.0 * kPi);
  r.aperiodic = t.aperiodic();
  const auto tr = t.transient(0.0, r.v_t, r.v_t);
  r.peak = tr.peak_m;
  r.settling = tr.settling_s;
  if (!std::isfinite(r.q_ss) || !std::isfinite(r.peak) || !std::isfinite(r.settling))
    throw io::InputError(who +
                         "the inputs give no finite result: --s · --n (the carriage feed), --P0, "
                         "--E0, --C0, --M and --i are too far apart");
  require_finite<Result>(who, r, kOutputs, "--E0, --C0, --M, --i, --P0, --s and --n");
  nlohmann::json more = nlohmann::json::object();
  if (!characteristics_path.empty()) {
    io::write_file_atomic(characteristics_path, characteristics_csv(t, r.v_t));
    more["characteristics"] = characteristics_path;
  }
  const int rc = print_result<Args, Result>(
      a, kInputs, r, kOutputs,
      "Hydraulic tracer slide, linearised (seed 002, (8)-(9), (12)-(13))", more);
  if (!a.json && !characteristics_path.empty())
    std::printf("  static characteristics (Fig. 1) in %s\n", characteristics_path.c_str());
  return rc;
}

void add(CLI::App& sub, Commands& out) {
  characteristics_path.clear();  // per command line: the Python module parses many in one process
  add_calculator<Args>(sub, out, kInputs,
                       "Seed 002 and its formulas (8)-(9), (12)-(13), Fig. 1: " +
                           doc("system-c-tracer.md") + ".",
                       &compute);
  sub.add_option("--characteristics", characteristics_path,
                 "write the static characteristics of (9) (the seed's Fig. 1: P(h) at V_k = 0 "
                 "and v_T, V_k(h) at P = 0 and P0) to this CSV file");
}

std::string reference() {
  return calculator_reference<Args, Result>(kInputs, kOutputs);
}

std::vector<CalculatorInput> inputs() { return input_rows<Args>(kInputs); }

}  // namespace

const Calculator kTracer{
    "tracer",
    "Seed 002: linearised hydraulic tracer slide — steady lag on a cone (P0/E0 + v_T/C0)/i, "
    "the profile errors δx, δy (12)-(13), damping ratio, natural frequency, transient lag and "
    "settling at a cylinder→cone change, the static characteristics (Fig. 1)",
    &add, &reference, &inputs};

}  // namespace lathectl::cli
