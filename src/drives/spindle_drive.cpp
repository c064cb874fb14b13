#include "lathectl/drives/spindle_drive.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::drives {


void SpindleDrive::configure(const Params& p) {
  if (!(p.inertia_kg_m2 > 0.0)) throw std::invalid_argument("spindle drive: inertia must be > 0");
  if (!(p.viscous_N_m_s >= 0.0))
    throw std::invalid_argument("spindle drive: viscous friction must be >= 0");
  if (!(p.max_torque_N_m > 0.0) || !(p.max_power_W > 0.0))
    throw std::invalid_argument("spindle drive: max torque and max power must be > 0");
  if (!(p.efficiency > 0.0 && p.efficiency <= 1.0))
    throw std::invalid_argument("spindle drive: efficiency must be in (0, 1]");
  if (!(p.idle_p0_W >= 0.0) || !(p.idle_p1_W_per_rpm >= 0.0) || !(p.idle_p2_W_per_rpm2 >= 0.0))
    throw std::invalid_argument("spindle drive: idle power coefficients must be >= 0");
  if (!(p.kp_N_m_s > 0.0) || !(p.ti_s > 0.0))
    throw std::invalid_argument("spindle drive: speed-loop kp and ti must be > 0");
  if (!(p.max_accel_rpm_per_s > 0.0))
    throw std::invalid_argument("spindle drive: max_accel_rpm_per_s must be > 0");
  if (!(p.min_rpm >= 0.0) || !(p.max_rpm > p.min_rpm) || !std::isfinite(p.max_rpm))
    throw std::invalid_argument("spindle drive: need 0 <= min_rpm < max_rpm");
  p_ = p;
  reset(0.0);
}

void SpindleDrive::reset(double rpm) noexcept {
  w_ = rpm * kRadPerSPerRpm;
  w_cmd_ = w_;
  integral_ = p_.viscous_N_m_s * w_;  // the torque that holds the speed without load
  tm_ = integral_;
  limited_ = false;
}

double idle_power_W(const SpindleDrive::Params& p, double rpm) noexcept {
  const double n = std::abs(rpm);
  return p.idle_p0_W + p.idle_p1_W_per_rpm * n + p.idle_p2_W_per_rpm2 * n * n;
}

double air_power_W(const SpindleDrive::Params& p, double rpm) noexcept {
  const double w = std::abs(rpm) * 2.0 * std::numbers::pi / 60.0;
  return idle_power_W(p, rpm) + p.viscous_N_m_s * w * w / p.efficiency;
}

double SpindleDrive::idle_power_W(double rpm) const noexcept {
  return drives::idle_power_W(p_, rpm);
}

double drawn_power_W(const SpindleDrive::Params& p, double mech_W) noexcept {
  // Motoring draws mech/η; regenerating returns only η of the braking power.
  return mech_W >= 0.0 ? mech_W / p.efficiency : mech_W * p.efficiency;
}

double SpindleDrive::electrical_power_W() const noexcept {
  return drawn_power_W(p_, tm_ * w_) + idle_power_W(rpm());
}

void SpindlePowerAtSpeed::configure(const SpindleDrive::Params& p, Drift d) {
  if (!(p.efficiency > 0.0 && p.efficiency <= 1.0))
    throw std::invalid_argument("spindle drive: efficiency must be in (0, 1]");
  if (!(d.factor >= 0.0) || !(d.warmup_s > 0.0))
    throw std::invalid_argument("spindle drive: idle drift must be >= 0, its warm-up time > 0");
  p_ = p;
  d_ = d;
  reset(0.0);
}

void SpindlePowerAtSpeed::reset(double rpm) noexcept {
  rpm_ = std::abs(rpm);
  t_s_ = 0.0;
  idle_W_ = 0.0;
}

double SpindlePowerAtSpeed::idle_factor() const noexcept {
  return 1.0 + d_.factor * std::exp(-t_s_ / d_.warmup_s);
}

double SpindlePowerAtSpeed::step(double dt, double rpm, double cut_power_W) noexcept {
  const double n = std::abs(rpm);
  const double w = n * kRadPerSPerRpm;
  const double dw = dt > 0.0 ? (n - rpm_) * kRadPerSPerRpm / dt : 0.0;
  rpm_ = n;
  t_s_ += dt;
  idle_W_ = n > 0.0 ? drives::idle_power_W(p_, n) * idle_factor() : 0.0;
  const double mech = cut_power_W + p_.inertia_kg_m2 * w * dw + p_.viscous_N_m_s * w * w;
  return drawn_power_W(p_, mech) + idle_W_;
}

}  // namespace lathectl::drives
