// threshold = "calibrated_dynamic": S_th adjusted on parts machined with the full model
// (rig.hpp says how).
#include <algorithm>
#include <cmath>
#include <vector>

#include "lathectl/core/parallel.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "systems/d_gauging/rig.hpp"

namespace lathectl::systems::d_gauging {

namespace {

// Without noise each part is exact and its finished size falls monotonically with the threshold
// (a higher S_th trips later), though not smoothly: the ripple left on S moves the crossing by
// uneven amounts as the threshold rises, so re-aiming through the slope K circles the target.
// A bracket is found by such steps, then narrowed by regula falsi (Illinois) to within
// precision_m (at most 0.05 µm), or to where the size jumps across the target.
DynamicCalibration calibrate_noiseless(const GaugingProcess& p,
                                       const sensors::VibroContactGauge::Params& gp, double dt,
                                       double threshold0_V, double gain_V_per_m,
                                       std::size_t max_parts, double precision_m,
                                       std::uint64_t seed, double max_time_s) {
  DynamicCalibration c;
  const double tol = std::min(precision_m, 0.05e-6);
  auto error_at = [&](double th) {
    ++c.parts;
    return machine_part_full(p, gp, dt, th, seed, nullptr, 50, max_time_s).finished_m - p.target_m;
  };
  auto accept = [&](double th, double e) {
    c.threshold_V = th;
    c.mean_error_m = e;
    c.converged = std::abs(e) <= tol;
    if (c.converged) c.jump_m = 0.0;
    return c;
  };
  double a = threshold0_V, ea = error_at(a);
  if (std::abs(ea) <= tol || c.parts >= max_parts) return accept(a, ea);
  // Bracket: step by K·e (doubling while the sign holds).
  double step = gain_V_per_m * ea;
  double b = a + step, eb = error_at(b);
  while ((ea > 0.0) == (eb > 0.0) && std::abs(eb) > tol && c.parts < max_parts) {
    a = b;
    ea = eb;
    step *= 2.0;
    b = a + step;
    eb = error_at(b);
  }
  if (std::abs(eb) <= tol || (ea > 0.0) == (eb > 0.0) || c.parts >= max_parts)
    return std::abs(eb) <= std::abs(ea) ? accept(b, eb) : accept(a, ea);
  int side = 0;  // Illinois: halve the weight of an end kept twice
  c.jump_m = ea - eb;  // narrowed with the bracket
  while (c.parts < max_parts && std::abs(b - a) > 1e-12) {
    const double m = (a * eb - b * ea) / (eb - ea);
    const double em = error_at(m);
    if (std::abs(em) <= tol) return accept(m, em);
    if ((em > 0.0) == (ea > 0.0)) {
      a = m;
      ea = em;
      if (side == -1) eb *= 0.5;
      side = -1;
    } else {
      b = m;
      eb = em;
      if (side == 1) ea *= 0.5;
      side = 1;
    }
  }
  c.jump_m = ea - eb;
  c.bracket_V = std::abs(b - a);
  return std::abs(eb) <= std::abs(ea) ? accept(b, eb) : accept(a, ea);
}

}  // namespace

DynamicCalibration calibrate_dynamic(const GaugingProcess& p,
                                     const sensors::VibroContactGauge::Params& gp, double dt,
                                     double threshold0_V, double gain_V_per_m,
                                     std::size_t max_parts, double precision_m, std::uint64_t seed,
                                     double max_time_s) {
  const bool noisy = p.noise_variance_m2 > 0.0;
  if (!noisy)
    return calibrate_noiseless(p, gp, dt, threshold0_V, gain_V_per_m, max_parts, precision_m,
                               seed, max_time_s);
  const std::size_t batch = 8;
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
    auto [m, se] = pooled(c.threshold_V);
    c.mean_error_m = m;
    c.standard_error_m = se;
    const bool done = err_at_th.size() > 1 && std::abs(m) <= se && se <= precision_m;
    if (done) {
      c.converged = true;
      break;
    }
    c.threshold_V += gain_V_per_m * m;
    const auto after = pooled(c.threshold_V);  // the pooled estimate at the new threshold
    c.mean_error_m = after.first;
    c.standard_error_m = after.second;
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

MachineThreshold machine_threshold(const Settings& d, const GaugingProcess& p,
                                   const ThresholdPlan& plan, double dt, std::uint64_t seed,
                                   double max_time_s, std::size_t kept) {
  MachineThreshold m;
  m.static_V = m.threshold_V = plan.threshold_V;
  const bool dynamic = d.threshold == "calibrated_dynamic";
  if (d.threshold != "calibrated" && !dynamic) return m;
  const auto line = linear_gauge(plan.calibrated_line, d.transducer);
  if (p.noise_variance_m2 > 0.0) {
    LinearParts cal(p, line, plan.threshold_V, d.parts, seed + 1000003, kept);
    m.bias = first_passage_bias(cal, p.target_m, line.gain_V_per_m);
    auto q = p;
    q.target_m -= m.bias.bias_m;
    m.static_V = m.threshold_V = threshold_23(line, q);
  }
  if (dynamic) {
    auto aim = p;
    aim.noise_variance_m2 = 0.0;
    aim.target_m -= m.bias.bias_m;
    const double judge_se = std::sqrt(p.noise_variance_m2 *
                                      line.noise_factor(p.noise_beta_per_s) /
                                      static_cast<double>(d.parts));
    m.dyn = calibrate_dynamic(aim, d.transducer, dt, m.static_V, line.gain_V_per_m,
                              d.calibration_parts_max, std::max(0.1 * judge_se, 1e-10),
                              seed + 17, max_time_s);
    m.threshold_V = m.dyn.threshold_V;
  }
  return m;
}

}  // namespace lathectl::systems::d_gauging
