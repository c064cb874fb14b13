#include "lathectl/drives/eccentric_drive.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::drives {

namespace {
double interp(const std::vector<double>& xs, const std::vector<double>& ys, double x) noexcept {
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto it = std::upper_bound(xs.begin(), xs.end(), x);
  const auto i = static_cast<std::size_t>(it - xs.begin());
  const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}
}  // namespace

void EccentricDrive::circular_profile(double base, double e, int n, Params& p) {
  p.profile_angle_rad.clear();
  p.profile_slot_m.clear();
  for (int k = 0; k < n; ++k) {
    const double th = std::numbers::pi * k / (n - 1);
    p.profile_angle_rad.push_back(th);
    p.profile_slot_m.push_back(base + e * (1.0 - std::cos(th)));
  }
}

void EccentricDrive::configure(const Params& p) {
  const auto n = p.profile_angle_rad.size();
  if (n < 2 || p.profile_slot_m.size() != n)
    throw std::invalid_argument("eccentric profile: at least two (angle, slot) points expected");
  for (std::size_t i = 1; i < n; ++i)
    if (!(p.profile_angle_rad[i] > p.profile_angle_rad[i - 1]) ||
        !(p.profile_slot_m[i] > p.profile_slot_m[i - 1]))
      throw std::invalid_argument("eccentric profile: angle and slot must both strictly increase");
  if (p.profile_slot_m.front() < 0.0) throw std::invalid_argument("eccentric profile: slot < 0");
  if (!(p.position_gain_per_s > 0.0) || !(p.motor_max_speed_rad_per_s > 0.0) ||
      !(p.gear_ratio > 0.0) || !(p.motor_time_constant_s >= 0.0))
    throw std::invalid_argument("eccentric drive: gain, speed and ratio must be > 0");
  p_ = p;
  last_dt_ = -1.0;
  last_cmd_ = -1.0;
  set_slot(p.profile_slot_m.front());
}

double EccentricDrive::slot_of(double a) const noexcept {
  return interp(p_.profile_angle_rad, p_.profile_slot_m, a);
}
double EccentricDrive::angle_of(double s) const noexcept {
  return interp(p_.profile_slot_m, p_.profile_angle_rad, s);
}

void EccentricDrive::set_slot(double s) noexcept {
  theta_ = angle_of(s);
  omega_ = 0.0;
  slot_ = slot_of(theta_);
}

void EccentricDrive::step(double dt, double slot_cmd) noexcept {
  if (slot_cmd != last_cmd_) {  // the command changes once per control period, not every step
    last_cmd_ = slot_cmd;
    target_ = angle_of(slot_cmd);
  }
  const double target = target_;
  const double w_cmd = std::clamp(p_.position_gain_per_s * (target - theta_) * p_.gear_ratio,
                                  -p_.motor_max_speed_rad_per_s, p_.motor_max_speed_rad_per_s);
  if (dt != last_dt_) {
    last_dt_ = dt;
    motor_lag_ = core::FirstOrderLag(dt, p_.motor_time_constant_s);
  }
  const double w_new = motor_lag_.step(omega_, w_cmd);
  theta_ += 0.5 * (omega_ + w_new) / p_.gear_ratio * dt;
  omega_ = w_new;
  const double lo = p_.profile_angle_rad.front();
  const double hi = p_.profile_angle_rad.back();
  if (theta_ <= lo || theta_ >= hi) {
    theta_ = std::clamp(theta_, lo, hi);
    omega_ = 0.0;  // on the end stop
  }
  slot_ = slot_of(theta_);
}

}  // namespace lathectl::drives
