#include "lathectl/dynamics/delayed_coupling.hpp"

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace lathectl::dynamics {

namespace {
std::complex<double> loop(const std::vector<Mode>& modes, double w, double T, double c) {
  std::complex<double> phi{0.0, 0.0};
  for (const Mode& m : modes) {
    const double r = w / (2.0 * std::numbers::pi * m.natural_frequency_Hz);
    const double cs = std::cos(m.angle_rad);
    phi += cs * cs /
           (m.stiffness_N_per_m * std::complex<double>(1.0 - r * r, 2.0 * m.damping_ratio * r));
  }
  return phi * (1.0 - c * std::exp(std::complex<double>(0.0, -w * T)));
}
}  // namespace

CriticalGain critical_gain(const std::vector<Mode>& modes, double T, double c, double f_lo,
                           double f_hi, int points) {
  if (modes.empty() || !(T > 0.0) || !(f_lo > 0.0) || !(f_hi > f_lo) || points < 10)
    throw std::invalid_argument("critical_gain: modes, delay > 0, 0 < f_lo < f_hi, points ≥ 10");
  const double two_pi = 2.0 * std::numbers::pi;
  CriticalGain best{std::numeric_limits<double>::infinity(), 0.0};
  double w_prev = two_pi * f_lo;
  double im_prev = loop(modes, w_prev, T, c).imag();
  for (int i = 1; i <= points; ++i) {
    const double w = two_pi * (f_lo + (f_hi - f_lo) * i / points);
    const double im = loop(modes, w, T, c).imag();
    if ((im_prev < 0.0) != (im < 0.0)) {
      double a = w_prev, b = w, fa = im_prev;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (a + b);
        const double fm = loop(modes, mid, T, c).imag();
        if ((fa < 0.0) == (fm < 0.0)) {
          a = mid;
          fa = fm;
        } else {
          b = mid;
        }
      }
      const double wc = 0.5 * (a + b);
      const double re = loop(modes, wc, T, c).real();
      if (re < 0.0 && -1.0 / re < best.gain_N_per_m) best = {-1.0 / re, wc / two_pi};
    }
    w_prev = w;
    im_prev = im;
  }
  return best;
}

}  // namespace lathectl::dynamics
