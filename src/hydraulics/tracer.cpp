#include "lathectl/hydraulics/tracer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::hydraulics {

double TracerLinear::omega_n() const noexcept {
  return std::sqrt(lever_ratio * E0_N_per_m / mass_kg);
}
double TracerLinear::zeta() const noexcept {
  return std::sqrt(E0_N_per_m / (mass_kg * lever_ratio)) / (2.0 * C0_per_s);
}
double TracerLinear::steady_lag_m(double v) const noexcept {
  return (P0_N / E0_N_per_m + v / C0_per_s) / lever_ratio;
}

double TracerLinear::lag(double q0, double qd0, double v, double tau) const noexcept {
  // Roots of (M/E0)λ² + λ/C0 + i = 0.
  const double a = mass_kg / E0_N_per_m, b = 1.0 / C0_per_s, c = lever_ratio;
  const double q_ss = v / (C0_per_s * lever_ratio);
  const double disc = b * b - 4.0 * a * c;
  const double y0 = q0 - q_ss, yd0 = qd0;
  if (std::abs(disc) < 1e-12 * b * b) {  // critically damped: (A + B τ) e^{λτ}
    const double l = -b / (2.0 * a);
    return q_ss + (y0 + (yd0 - l * y0) * tau) * std::exp(l * tau);
  }
  const std::complex<double> sq = std::sqrt(std::complex<double>(disc, 0.0));
  const std::complex<double> l1 = (-b + sq) / (2.0 * a), l2 = (-b - sq) / (2.0 * a);
  const std::complex<double> c1 = (yd0 - l2 * y0) / (l1 - l2);
  const std::complex<double> c2 = y0 - c1;
  return q_ss + std::real(c1 * std::exp(l1 * tau) + c2 * std::exp(l2 * tau));
}

ProfileError cone_profile_error(double q, double alpha, double beta) noexcept {
  const double s = std::sin(alpha + beta), sa = std::sin(alpha), ca = std::cos(alpha);
  // |sin α|, |cos α| below 1e-12: a cylinder or a shoulder, where (12) or (13) has no equal y or x.
  return {std::abs(sa) < 1e-12 ? NAN : q * s / sa, std::abs(ca) < 1e-12 ? NAN : 0.0 - q * s / ca};
}

TracerLinear::Transient TracerLinear::transient(double q0, double qd0, double v) const noexcept {
  const double q_ss = v / (C0_per_s * lever_ratio);
  const double slowest =
      1.0 / (zeta() * omega_n() >= omega_n()
                 ? omega_n() * (zeta() - std::sqrt(std::max(zeta() * zeta() - 1.0, 0.0)))
                 : zeta() * omega_n());
  const double horizon = 20.0 * slowest + 20.0 / omega_n();
  const int n = 20000;
  Transient t{0.0, 0.0};
  const double scale = std::max(std::abs(q_ss - q0), std::abs(q_ss));
  for (int k = 0; k <= n; ++k) {
    const double tau = horizon * k / n;
    const double q = lag(q0, qd0, v, tau);
    t.peak_m = std::max(t.peak_m, std::abs(q));
    if (std::abs(q - q_ss) > 0.02 * scale) t.settling_s = tau;
  }
  return t;
}

void TemplateProfile::add_point(double x, double y) {
  if (!x_.empty() && x < x_.back()) throw std::invalid_argument("template: x must not decrease");
  x_.push_back(x);
  y_.push_back(y);
}

double TemplateProfile::y_at(double x) const noexcept {
  if (x_.empty()) return 0.0;
  if (x <= x_.front()) return y_.front();
  if (x >= x_.back()) return y_.back();
  // upper_bound: on a vertical step (equal x) take the later (upper/lower) point's side.
  const auto it = std::upper_bound(x_.begin(), x_.end(), x);
  const auto i = static_cast<std::size_t>(it - x_.begin());
  const double dx = x_[i] - x_[i - 1];
  if (dx <= 0.0) return y_[i];
  return y_[i - 1] + (y_[i] - y_[i - 1]) * (x - x_[i - 1]) / dx;
}

double slide_target(const TemplateProfile& tp, double x_c, double y0, double beta, double lo,
                    double hi) noexcept {
  const double sb = std::sin(beta), cb = std::cos(beta);
  auto f = [&](double s) { return y0 + s * sb - tp.y_at(x_c - s * cb); };  // increasing in s
  double flo = f(lo);
  if (flo > 0.0) return lo;
  if (f(hi) < 0.0) return hi;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    const double fm = f(mid);
    if ((fm > 0.0) == (flo > 0.0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace lathectl::hydraulics
