#include "optimize/path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace lathectl::optimize {

double arc_sweep(const io::CanonMove& m) noexcept {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const double a0 = std::atan2(m.x0 - m.xc, m.z0 - m.zc);
  const double a1 = std::atan2(m.x1 - m.xc, m.z1 - m.zc);
  double d = a1 - a0;
  const double turns = static_cast<double>(std::abs(m.rotation) - 1);
  if (m.rotation > 0) {
    while (d <= 1e-12) d += kTwoPi;
    return d + kTwoPi * turns;
  }
  while (d >= -1e-12) d -= kTwoPi;
  return d - kTwoPi * turns;
}

double move_length(const io::CanonMove& m) noexcept {
  if (m.kind != io::CanonMove::Kind::Arc) return std::hypot(m.x1 - m.x0, m.z1 - m.z0);
  return std::hypot(m.x0 - m.xc, m.z0 - m.zc) * std::abs(arc_sweep(m));
}

std::pair<double, double> point_at(const io::CanonMove& m, double u) noexcept {
  if (m.kind != io::CanonMove::Kind::Arc)
    return {m.x0 + (m.x1 - m.x0) * u, m.z0 + (m.z1 - m.z0) * u};
  if (u >= 1.0) return {m.x1, m.z1};
  const double r = std::hypot(m.x0 - m.xc, m.z0 - m.zc);
  const double a = std::atan2(m.x0 - m.xc, m.z0 - m.zc) + arc_sweep(m) * u;
  return {m.xc + r * std::sin(a), m.zc + r * std::cos(a)};
}

double spindle_rpm(const io::CanonMove& m, double x_mm) {
  if (!m.spindle_on) return 0.0;
  if (!m.css) return m.speed;
  // G96: n = 1000·V / (2π·|x|), at most D (LinuxCNC's css, X the radius)
  const double cap = m.css_max_rpm > 0.0 ? m.css_max_rpm : std::numeric_limits<double>::infinity();
  const double r = std::abs(x_mm);
  return r > 1e-9 ? std::min(cap, 1000.0 * m.speed / (2.0 * std::numbers::pi * r)) : cap;
}

}  // namespace lathectl::optimize
