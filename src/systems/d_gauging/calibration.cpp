// threshold = "calibrated_dynamic": S_th adjusted on parts machined with the full model
// (rig.hpp says how).
#include <algorithm>
#include <cmath>
#include <vector>

#include "lathectl/core/parallel.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "systems/d_gauging/rig.hpp"

namespace lathectl::systems::d_gauging {

DynamicCalibration calibrate_dynamic(const GaugingProcess& p,
                                     const sensors::VibroContactGauge::Params& gp, double dt,
                                     double threshold0_V, double gain_V_per_m,
                                     std::size_t max_parts, double precision_m, std::uint64_t seed,
                                     double max_time_s) {
  const bool noisy = p.noise_variance_m2 > 0.0;
  const std::size_t batch = noisy ? 8 : 1;
  DynamicCalibration c;
  c.threshold_V = threshold0_V;
  std::vector<double> err_at_th;  // each part's error and the threshold it was machined at
  std::vector<double> th_of;
  while (c.parts < max_parts) {
    const std::size_t n = std::min(batch, max_parts - c.parts);
    std::vector<double> e(n);
    const double th = c.threshold_V;
    core::parallel_for(n, [&](std::size_t i) {  // part k: its own seed, apart from the study's
      const auto r =
          machine_part_full(p, gp, dt, th, seed * 104729 + c.parts + i, nullptr, 50, max_time_s);
      e[i] = r.finished_m - p.target_m;
    });
    for (double v : e) {
      err_at_th.push_back(v);
      th_of.push_back(th);
    }
    c.parts += n;
    // Pooled at the current threshold: a higher S_th trips at a smaller x (S = K·(B − x)).
    auto pooled = [&](double at) {
      double m = 0.0, m2 = 0.0;
      for (std::size_t k = 0; k < err_at_th.size(); ++k) {
        const double v = err_at_th[k] - (at - th_of[k]) / gain_V_per_m;
        m += v;
        m2 += v * v;
      }
      const double N = static_cast<double>(err_at_th.size());
      m /= N;
      const double var = N > 1.0 ? std::max(0.0, (m2 - N * m * m) / (N - 1.0)) : 0.0;
      return std::pair{m, std::sqrt(var / N)};
    };
    // Without noise each part is exact at its own threshold: the last one is the estimate.
    auto [m, se] = noisy ? pooled(c.threshold_V) : std::pair{err_at_th.back(), 0.0};
    c.mean_error_m = m;
    c.standard_error_m = se;
    const bool done = noisy ? (err_at_th.size() > 1 && std::abs(m) <= se && se <= precision_m)
                            : std::abs(m) <= 0.05e-6;
    if (done) {
      c.converged = true;
      break;
    }
    c.threshold_V += gain_V_per_m * m;
    if (noisy) {
      const auto after = pooled(c.threshold_V);  // the pooled estimate at the new threshold
      c.mean_error_m = after.first;
      c.standard_error_m = after.second;
    }
  }
  return c;
}

NoiselessPart noiseless_part(const GaugingProcess& quiet,
                             const sensors::VibroContactGauge::Params& gp, double dt,
                             std::uint64_t seed, double max_time_s) {
  const double lag = sensors::VibroContactGauge::filter_lag_s(gp) + quiet.relay_response_s;
  const double x_trip = quiet.target_m + quiet.removal_m_per_s * lag;
  const auto line = design::calibrated_line(gp, dt, x_trip);
  const double th = design::threshold_23(line, quiet.target_m, quiet.removal_m_per_s, lag);
  const auto r = machine_part_full(quiet, gp, dt, th, seed, nullptr, 50, max_time_s);
  const auto lv = sensors::VibroContactGauge::settled_signal(gp, dt, x_trip,
                                                             design::full_model_settle(gp), 0.4);
  return {r.finished_m - quiet.target_m, line.spread_m, lv.ripple_V};
}

}  // namespace lathectl::systems::d_gauging
