#include "lathectl/dynamics/van_der_pol.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "lathectl/dynamics/rk4.hpp"

namespace lathectl::dynamics {

QuenchResult van_der_pol_forced(double eps, double W, double E, double duration, double seed) {
  const double period = 2.0 * std::numbers::pi / std::max(1.0, W);
  const double dt = period / 200.0;
  const auto steps = static_cast<std::size_t>(duration / dt);
  double x = E / (1.0 - W * W) + seed, v = 0.0, t = 0.0;  // forced response + a self-excited seed
  auto f = [&](double tt, double xx, double vv) {
    return eps * (1.0 - xx * xx) * vv - xx + E * std::cos(W * tt);
  };
  // Two windows: the run's second quarter and its last quarter.
  std::vector<double> ts1, xs1, ts2, xs2;
  for (std::size_t k = 0; k < steps; ++k) {
    rk4_step(f, t, dt, x, v);
    t += dt;
    if (4 * k >= steps && 4 * k < 2 * steps) {
      ts1.push_back(t);
      xs1.push_back(x);
    }
    if (4 * k >= 3 * steps) {
      ts2.push_back(t);
      xs2.push_back(x);
    }
  }
  // Least squares x ≈ c·cos Ωt + s·sin Ωt over a window; the rest is the self-excited part.
  auto split = [W](const std::vector<double>& ts, const std::vector<double>& xs, double& forced) {
    double cc = 0, ss = 0, cs = 0, cx = 0, sx = 0;
    for (std::size_t i = 0; i < ts.size(); ++i) {
      const double c = std::cos(W * ts[i]), s = std::sin(W * ts[i]);
      cc += c * c;
      ss += s * s;
      cs += c * s;
      cx += c * xs[i];
      sx += s * xs[i];
    }
    const double det = cc * ss - cs * cs;
    const double a = (cx * ss - sx * cs) / det, b = (sx * cc - cx * cs) / det;
    double rest2 = 0.0;
    for (std::size_t i = 0; i < ts.size(); ++i) {
      const double r = xs[i] - a * std::cos(W * ts[i]) - b * std::sin(W * ts[i]);
      rest2 += r * r;
    }
    forced = std::hypot(a, b);
    return std::sqrt(2.0 * rest2 / static_cast<double>(ts.size()));  // RMS → amplitude
  };
  QuenchResult q;
  double forced_mid = 0.0;
  q.self_amplitude_mid = split(ts1, xs1, forced_mid);
  q.self_amplitude = split(ts2, xs2, q.forced_amplitude);
  return q;
}

double quenching_threshold(double eps, double W) {
  const double gain = 1.0 / std::abs(1.0 - W * W);  // forcing → forced amplitude, linear estimate
  double lo = 0.0, hi = 4.0 / gain;                 // B from 0 to 4
  const double duration = 40.0 / eps;               // growth/decay e-folds in ~2/(ε·margin)
  for (int k = 0; k < 30; ++k) {
    const double mid = 0.5 * (lo + hi);
    const auto q = van_der_pol_forced(eps, W, mid, duration, 0.05);
    (q.self_amplitude < q.self_amplitude_mid ? hi : lo) = mid;
  }
  return van_der_pol_forced(eps, W, hi, duration, 0.05).forced_amplitude;
}

}  // namespace lathectl::dynamics
