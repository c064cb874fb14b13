#include "lathectl/drives/feed_axis.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::drives {

namespace {
double quantise(double z, double resolution) noexcept {
  return std::round(z / resolution) * resolution;
}
}  // namespace

void FeedAxis::configure(const Params& p, double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s))
    throw std::invalid_argument("feed axis: time step dt must be > 0");
  if (!(p.time_constant_s >= 0.0))
    throw std::invalid_argument("feed axis: time_constant_s must be >= 0");
  if (!(p.max_velocity_m_per_s > 0.0) || !(p.max_acceleration_m_per_s2 > 0.0))
    throw std::invalid_argument(
        "feed axis: max_velocity_m_per_s and max_acceleration_m_per_s2 must be > 0");
  if (!(p.encoder_resolution_m > 0.0))
    throw std::invalid_argument("feed axis: encoder_resolution_m must be > 0");
  if (!(p.velocity_window_s > 0.0) || !std::isfinite(p.velocity_window_s))
    throw std::invalid_argument("feed axis: velocity_window_s must be > 0");
  const double window_steps = std::max(1.0, std::round(p.velocity_window_s / dt_s));
  if (window_steps > 1e7)
    throw std::invalid_argument("feed axis: velocity_window_s / dt exceeds 1e7 steps");
  p_ = p;
  dt_ = dt_s;
  lag_ = core::FirstOrderLag(dt_s, p.time_constant_s);
  hist_.assign(static_cast<std::size_t>(window_steps) + 1, 0.0);
  reset(0.0, 0.0);
}

void FeedAxis::reset(double z_m, double v_m_per_s) noexcept {
  z_ = z_m;
  v_ = v_m_per_s;
  v_meas_ = v_m_per_s;
  if (hist_.empty()) return;  // not configured
  // Newest at head_, oldest (window steps ago) just after it: steady motion at v until now.
  const std::size_t n = hist_.size();
  head_ = n - 1;
  for (std::size_t j = 0; j < n; ++j)
    hist_[n - 1 - j] =
        quantise(z_m - v_m_per_s * static_cast<double>(j) * dt_, p_.encoder_resolution_m);
}

void FeedAxis::step(double v_cmd_m_per_s) noexcept {
  const double v_ref = std::clamp(v_cmd_m_per_s, -p_.max_velocity_m_per_s, p_.max_velocity_m_per_s);
  double v_new = lag_.step(v_, v_ref);
  const double dv_max = p_.max_acceleration_m_per_s2 * dt_;
  if (std::abs(v_new - v_) > dv_max) v_new = v_ + std::copysign(dv_max, v_new - v_);
  z_ += 0.5 * (v_ + v_new) * dt_;
  v_ = v_new;
  if (hist_.empty()) return;  // not configured: no encoder
  const std::size_t n = hist_.size();
  head_ = head_ + 1 == n ? 0 : head_ + 1;
  hist_[head_] = quantise(z_, p_.encoder_resolution_m);
  const std::size_t oldest = head_ + 1 == n ? 0 : head_ + 1;
  v_meas_ = (hist_[head_] - hist_[oldest]) / (static_cast<double>(n - 1) * dt_);
}

}  // namespace lathectl::drives
