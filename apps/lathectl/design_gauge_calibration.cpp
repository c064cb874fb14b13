// `lathectl design gauge --calibration FILE.csv`: seed 003's (20), (22), (23), (25) on a line
// measured on the transducer instead of one computed from its coil and probe
// (design/gauge_calibration.hpp says how the line, A0 and the noise are found).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>

#include "calculator.hpp"
#include "design_gauge.hpp"
#include "lathectl/design/gauge_calibration.hpp"
#include "lathectl/io/calibration_reader.hpp"
#include "lathectl/io/errors.hpp"

namespace lathectl::cli {
namespace {

struct Result {
  double a0 = 0, K = 0, intercept = 0, noise = 0, residual = 0, r2 = 0, on_line = 0, points = 0;
  bool leaves = false;
  double s_target = 0, s_th = 0, t_k = 0, d_y = 0, sigma_y = 0, sigma_x = 0;
  std::optional<double> Cp;
};
const Output<Result> kOutputs[] = {
    {"A0: the curve leaves the line at", "A0_m", "m", "A0_um", "µm", 1e6, &Result::a0},
    {"signal gain K (−slope)", "K_V_per_m", "V/m", "K_mV_per_um", "mV/µm", 1e-3, &Result::K},
    {"intercept B0/q1 (20), zero crossing", "intercept_m", "m", "intercept_um", "µm", 1e6,
     &Result::intercept},
    {"calibration noise σ_n (chords)", "calibration_noise_V", "V", "calibration_noise_mV", "mV",
     1e3, &Result::noise},
    {"line's residual σ on [0, A0]", "fit_residual_V", "V", "fit_residual_mV", "mV", 1e3,
     &Result::residual},
    {"line's R² on [0, A0]", "r_squared", "", "r_squared", "", 1, &Result::r2},
    {"points on the line", "points_on_line", "", "points_on_line", "", 1, &Result::on_line},
    {"points measured", "points", "", "points", "", 1, &Result::points},
    {"curve seen leaving the line", "leaves", "", "leaves", "", 1, &Result::leaves},
    {"signal at target K·(B − x_k)", "S_target_V", "V", "S_target_V", "V", 1, &Result::s_target},
    {"threshold S_th (23)", "S_th_V", "V", "S_th_V", "V", 1, &Result::s_th},
    {"end of cut t_k (22)", "t_k_s", "s", "t_k_s", "s", 1, &Result::t_k},
    {"signal noise D_y (25)", "D_y_V2", "V²", "D_y_V2", "V²", 1, &Result::d_y},
    {"signal noise σ_y = sqrt(D_y)", "sigma_y_V", "V", "sigma_y_mV", "mV", 1e3, &Result::sigma_y},
    {"size scatter σ_x", "sigma_x_m", "m", "sigma_x_um", "µm", 1e6, &Result::sigma_x},
    {"Cp = 2·tol/(6·σ_x)", "Cp", "", "Cp", "", 1, &Result::Cp},
};

}  // namespace

int gauge_from_calibration(const CalibrationRun& run) {
  const std::string who = "design gauge: ";
  const auto points = io::read_calibration_file(run.path);
  design::CalibrationFit fit;
  try {
    fit = design::fit_calibration(points);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(who + "--calibration " + run.path + ": " + e.what());
  }
  const auto pn = design::process_numbers({fit.gain_V_per_m, fit.intercept_m}, run.in);
  Result r;
  r.a0 = fit.free_amplitude_m;
  r.K = fit.gain_V_per_m;
  r.intercept = fit.intercept_m;
  r.noise = fit.noise_sigma_V;
  r.residual = fit.residual_sigma_V;
  r.r2 = fit.r_squared;
  r.on_line = static_cast<double>(fit.points_on_line);
  r.points = static_cast<double>(fit.points);
  r.leaves = fit.leaves;
  r.s_target = pn.signal_at_target_V;
  r.s_th = pn.threshold_V;
  r.t_k = pn.end_time_s;
  r.d_y = pn.noise_variance_V2;
  r.sigma_y = std::sqrt(pn.noise_variance_V2);
  r.sigma_x = pn.size_sigma_m;
  // The relay trips where the size is x_k + a·(lag + t_r): that point must lie on the measured
  // line, [first point, A0], or the calibration does not vouch for (23) there.
  const double trip = run.in.target_m + pn.lag_m;
  if (!(trip >= points.front().allowance_m && trip <= fit.free_amplitude_m) && !run.force) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "--target-um %g: the relay trips at x_k + a·(T_f + t_r) = %.4g µm, outside the "
                  "calibrated line [%.4g, %.4g] µm of --calibration %s (--force to compute "
                  "anyway)",
                  run.in.target_m * 1e6, trip * 1e6, points.front().allowance_m * 1e6,
                  fit.free_amplitude_m * 1e6, run.path.c_str());
    throw io::InputError(who + buf);
  }
  if (run.tolerance_um)
    r.Cp = r.sigma_x > 0.0 ? 2.0 * *run.tolerance_um * 1e-6 / (6.0 * r.sigma_x)
                           : std::numeric_limits<double>::infinity();
  if (!fit.leaves)
    std::cerr << "note: the measured curve does not leave its line up to the last point ("
              << fit.free_amplitude_m * 1e6 << " µm): A0 is at least that\n";
  if (run.in.allowance_m > fit.free_amplitude_m)
    std::cerr << "note: allowance " << run.in.allowance_m * 1e6
              << " µm exceeds A0 = " << fit.free_amplitude_m * 1e6
              << " µm where the calibration leaves its line; the gauge reads nothing until x < A0\n";
  if (run.json) {
    nlohmann::json j;
    j["inputs"] = run.inputs;
    outputs_json<Result>(j, r, kOutputs);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  print_header("Vibro-contact gauge from a measured calibration (seed 003, (20)-(25))");
  print_outputs<Result>(r, kOutputs);
  return 0;
}

std::string calibration_outputs_markdown() { return outputs_markdown<Result>(kOutputs); }

}  // namespace lathectl::cli
