#pragma once
// AIM actuator of seed 000: amplifier У → electric motor ЭД with gearbox Р → eccentric 8, the
// stop of the regulator spool, whose angle θ sets the slot h = profile(θ).
//
//   θ_t = profile⁻¹(h_cmd)                                   (programmed profile, monotone)
//   ω_cmd = clamp(K_v · (θ_t − θ) · i, −ω_max, ω_max)         amplifier + motor speed limit
//   τ_m · dω/dt = ω_cmd − ω                                    motor (first order)
//   dθ/dt = ω / i,  θ ∈ [θ_0, θ_end]                           gearbox ratio i
// The motor lag is integrated exactly (e^(−dt/τ_m)); the angle by the trapezoid rule.
// The profile is a table of (θ, h) points, linear between them; the default is a circular
// eccentric h = h_0 + e·(1 − cos θ), θ ∈ [0, π].

#include <vector>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::drives {

class EccentricDrive {
 public:
  struct Params {
    std::vector<double> profile_angle_rad;  // ascending
    std::vector<double> profile_slot_m;     // strictly ascending (invertible)
    double position_gain_per_s = 20.0;      // K_v: eccentric speed per rad of error
    double motor_max_speed_rad_per_s = 300.0;
    double gear_ratio = 100.0;  // i: motor turns per eccentric turn
    double motor_time_constant_s = 0.02;
  };
  // Circular eccentric profile with n points.
  static void circular_profile(double base_slot_m, double eccentricity_m, int n, Params& p);

  void configure(const Params& p);        // throws std::invalid_argument
  void set_slot(double slot_m) noexcept;  // place the eccentric at rest at this slot
  void step(double dt, double slot_cmd_m) noexcept;
  [[nodiscard]] double slot_m() const noexcept { return slot_; }
  [[nodiscard]] double slot_of(double angle_rad) const noexcept;
  [[nodiscard]] double angle_of(double slot_m) const noexcept;

 private:
  Params p_{};
  double theta_ = 0.0;
  double omega_ = 0.0;  // motor speed
  double slot_ = 0.0;
  double last_dt_ = -1.0;      // the step motor_lag_ is for
  core::FirstOrderLag motor_lag_;
  double last_cmd_ = -1.0;  // cache of profile⁻¹ for the last command
  double target_ = 0.0;
};

}  // namespace lathectl::drives
