#include "lathectl/design/gauge_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace lathectl::design {

namespace {

// σ_n = 1.4826·median|r_i|, r_i the normalised chord residuals of the interior points.
double chord_noise(std::span<const CalibrationPoint> p) {
  std::vector<double> r;
  r.reserve(p.size());
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double span = p[i + 1].allowance_m - p[i - 1].allowance_m;
    const double wl = (p[i + 1].allowance_m - p[i].allowance_m) / span, wr = 1.0 - wl;
    const double chord = wl * p[i - 1].voltage_V + wr * p[i + 1].voltage_V;
    r.push_back(std::abs(p[i].voltage_V - chord) / std::sqrt(1.0 + wl * wl + wr * wr));
  }
  const auto mid = r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2);
  std::nth_element(r.begin(), mid, r.end());
  double m = *mid;
  if (r.size() % 2 == 0) m = 0.5 * (m + *std::max_element(r.begin(), mid));
  return 1.4826 * m;
}

struct Line {
  double c0 = 0.0, c1 = 0.0;  // V = c0 + c1·x
};

// Least squares over p[0..m), about the mean (no cancellation for x ~ 1e-4 m).
Line fit_line(std::span<const CalibrationPoint> p, std::size_t m) {
  double mx = 0.0, mv = 0.0;
  for (std::size_t i = 0; i < m; ++i) mx += p[i].allowance_m, mv += p[i].voltage_V;
  mx /= static_cast<double>(m);
  mv /= static_cast<double>(m);
  double sxx = 0.0, sxv = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    const double dx = p[i].allowance_m - mx;
    sxx += dx * dx;
    sxv += dx * (p[i].voltage_V - mv);
  }
  const double c1 = sxv / sxx;
  return {mv - c1 * mx, c1};
}

double worst_residual(std::span<const CalibrationPoint> p, std::size_t m, const Line& l) {
  double w = 0.0;
  for (std::size_t i = 0; i < m; ++i)
    w = std::max(w, std::abs(p[i].voltage_V - (l.c0 + l.c1 * p[i].allowance_m)));
  return w;
}

}  // namespace

CalibrationFit fit_calibration(std::span<const CalibrationPoint> p) {
  if (p.size() < kMinCalibrationPoints)
    throw std::invalid_argument("at least " + std::to_string(kMinCalibrationPoints) +
                                " calibration points expected, " + std::to_string(p.size()) +
                                " given");
  double v_lo = p[0].voltage_V, v_hi = p[0].voltage_V;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p[i].allowance_m) || !std::isfinite(p[i].voltage_V) ||
        p[i].allowance_m < 0.0 || (i > 0 && !(p[i].allowance_m > p[i - 1].allowance_m)))
      throw std::invalid_argument("the allowances must be finite, ≥ 0 and strictly ascending");
    v_lo = std::min(v_lo, p[i].voltage_V);
    v_hi = std::max(v_hi, p[i].voltage_V);
  }
  CalibrationFit f;
  f.points = p.size();
  f.noise_sigma_V = chord_noise(p);
  const double tol = std::max(kLeaveSigmas * f.noise_sigma_V, 1e-9 * (v_hi - v_lo));
  // The largest prefix [0, x_j] (at least three points) whose line keeps every residual in tol.
  std::size_t m = 0;
  for (std::size_t j = 3; j <= p.size(); ++j)
    if (worst_residual(p, j, fit_line(p, j)) <= tol) m = j;
  if (m == 0)
    throw std::invalid_argument(
        "no line through the first three points within 4σ of the noise: the curve does not "
        "start straight");
  const Line l = fit_line(p, m);
  if (!(l.c1 < 0.0))
    throw std::invalid_argument("the voltage does not fall as the allowance grows (slope " +
                                std::to_string(l.c1 * 1e-3) + " mV/µm): no gain K > 0");
  f.points_on_line = m;
  f.leaves = m < p.size();
  f.free_amplitude_m = p[m - 1].allowance_m;
  f.gain_V_per_m = -l.c1;
  f.intercept_m = l.c0 / -l.c1;
  double ss_res = 0.0, ss_tot = 0.0, mv = 0.0;
  for (std::size_t i = 0; i < m; ++i) mv += p[i].voltage_V;
  mv /= static_cast<double>(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double r = p[i].voltage_V - (l.c0 + l.c1 * p[i].allowance_m);
    ss_res += r * r;
    ss_tot += (p[i].voltage_V - mv) * (p[i].voltage_V - mv);
  }
  f.residual_sigma_V = m > 2 ? std::sqrt(ss_res / static_cast<double>(m - 2)) : 0.0;
  f.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 1.0;
  return f;
}

}  // namespace lathectl::design
