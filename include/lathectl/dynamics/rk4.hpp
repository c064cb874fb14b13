#pragma once
// One classical Runge–Kutta step for a second-order scalar system ẍ = a(t, x, ẋ), shared by the
// models that integrate one (tracer slide, van der Pol check). Fourth-order accurate in h.

namespace lathectl::dynamics {

template <class Accel>
inline void rk4_step(Accel&& a, double t, double h, double& x, double& v) noexcept {
  const double k1x = v, k1v = a(t, x, v);
  const double k2x = v + 0.5 * h * k1v, k2v = a(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v);
  const double k3x = v + 0.5 * h * k2v, k3v = a(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v);
  const double k4x = v + h * k3v, k4v = a(t + h, x + h * k3x, v + h * k3v);
  x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
  v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
}

}  // namespace lathectl::dynamics
