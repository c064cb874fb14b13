#pragma once
// Spindle drive (system E, drive 2 with speed sensor 13), and its electrical power draw (the
// power sensor of seeds 001 and 004).
//
//   J·dω/dt = T_m − T_cut − b·ω                         mechanics (ω [rad/s])
//   T_m = clamp(PI(ω_cmd − ω), −T_lim(ω), T_lim(ω))     speed loop, anti-windup
//   T_lim(ω) = min(T_max, P_max / max(|ω|, ω_base))     torque limit and constant-power range
//   P_el = T_m·ω / η + P_idle(n)                        electrical power drawn [W]
//   P_idle(n) = p0 + p1·n + p2·n²                       speed-dependent idle losses (n in rpm)
// Integration: semi-implicit Euler on ω (the viscous term implicit). The speed command is
// rate-limited by `max_accel_rpm_per_s` (the drive's ramp).

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lathectl::drives {

inline constexpr double kRadPerSPerRpm = 2.0 * std::numbers::pi / 60.0;

class SpindleDrive {
 public:
  struct Params {
    bool operator==(const Params&) const = default;
    double inertia_kg_m2 = 0.5;     // J (spindle, chuck, part) reduced to the spindle
    double viscous_N_m_s = 0.01;    // b
    double max_torque_N_m = 400.0;  // T_max
    double max_power_W = 15000.0;   // P_max (mechanical, at the spindle)
    double efficiency = 0.85;       // η of motor + transmission
    double idle_p0_W = 300.0;       // P_idle(n) = p0 + p1·n + p2·n²
    double idle_p1_W_per_rpm = 0.3;
    double idle_p2_W_per_rpm2 = 1e-4;
    double kp_N_m_s = 20.0;               // speed-loop proportional gain [N·m per rad/s]
    double ti_s = 0.05;                   // speed-loop integral time
    double max_accel_rpm_per_s = 2000.0;  // command ramp
    double min_rpm = 10.0;
    double max_rpm = 4000.0;
  };
  void configure(const Params& p);  // throws std::invalid_argument
  void reset(double rpm) noexcept;  // steady at rpm, no load
  // One step with the commanded speed [rpm] and the cutting torque [N·m].
  void step(double dt, double rpm_cmd, double load_torque_N_m) noexcept;
  [[nodiscard]] double rpm() const noexcept;
  [[nodiscard]] double omega() const noexcept { return w_; }
  [[nodiscard]] double motor_torque_N_m() const noexcept { return tm_; }
  [[nodiscard]] double electrical_power_W() const noexcept;
  [[nodiscard]] double idle_power_W(double rpm) const noexcept;
  [[nodiscard]] bool torque_limited() const noexcept { return limited_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  Params p_{};
  double w_ = 0.0;         // rad/s
  double w_cmd_ = 0.0;     // ramped command, rad/s
  double integral_ = 0.0;  // N·m
  double tm_ = 0.0;
  bool limited_ = false;
};

// The idle law P_idle(n) = p0 + p1·|n| + p2·n² [W] (n in rpm): what a running spindle draws
// without cutting. The drive, the rigs and the HAL components all use this one.
[[nodiscard]] double idle_power_W(const SpindleDrive::Params& p, double rpm) noexcept;
// What the drive draws turning steadily in air: the idle law and its viscous friction b·ω²/η
// (SpindleDrive::electrical_power_W at constant speed without a cutting torque).
[[nodiscard]] double air_power_W(const SpindleDrive::Params& p, double rpm) noexcept;

// The electrical power a drive draws for a mechanical power `mech_W` at the spindle: motoring
// draws mech/η, regenerating (braking) returns only η of it. SpindleDrive draws so.
[[nodiscard]] double drawn_power_W(const SpindleDrive::Params& p, double mech_W) noexcept;

// The drive's electrical power where the spindle's speed is given, not simulated (LinuxCNC's
// spindle in the simulated lathe lathectl_plant, the optimiser's predicted speed): the same law
// as SpindleDrive's, with the motor's torque from the load and the speed's change,
//   T_m·ω = P_cut + J·ω·dω/dt + b·ω²,   P_el = drawn(T_m·ω) + P_idle(n)·(1 + d·e^(−t/t_w))
// (dω/dt between successive speeds; d the idle law's warm-up drift, 0 by default: a cold
// spindle draws more than its law until it is warm).
struct IdleDrift {
  double factor = 0.0;      // d
  double warmup_s = 120.0;  // t_w
};
class SpindlePowerAtSpeed {
 public:
  using Drift = IdleDrift;
  void configure(const SpindleDrive::Params& p, Drift d = {});  // throws std::invalid_argument
  void reset(double rpm) noexcept;
  // One step of dt [s] to the speed rpm (sign ignored) with the cutting power [W]: P_el [W].
  double step(double dt, double rpm, double cut_power_W) noexcept;
  [[nodiscard]] double idle_factor() const noexcept;  // 1 + d·e^(−t/t_w)
  [[nodiscard]] double idle_power_W() const noexcept { return idle_W_; }

 private:
  SpindleDrive::Params p_{};
  Drift d_{};
  double rpm_ = 0.0, t_s_ = 0.0, idle_W_ = 0.0;
};

// The per-step path in the header: a rig steps the drive every step (issue 45 item 6).
inline void SpindleDrive::step(double dt, double rpm_cmd, double load_torque_N_m) noexcept {
  // Command ramp, then the speed loop.
  const double target = std::clamp(rpm_cmd, p_.min_rpm, p_.max_rpm) * kRadPerSPerRpm;
  const double dw_max = p_.max_accel_rpm_per_s * kRadPerSPerRpm * dt;
  w_cmd_ += std::clamp(target - w_cmd_, -dw_max, dw_max);

  const double w_base = p_.max_power_W / p_.max_torque_N_m;
  const double t_lim = std::min(p_.max_torque_N_m, p_.max_power_W / std::max(std::abs(w_), w_base));
  const double e = w_cmd_ - w_;
  const double p_term = p_.kp_N_m_s * e;
  // Conditional integration: hold the integral while the output is at its limit and the error
  // would push it further. The clamp drops what lies beyond a limit that has fallen with speed
  // (constant-power range), so recovery is not delayed.
  const double i_next = integral_ + p_.kp_N_m_s / p_.ti_s * e * dt;
  const double u_next = p_term + i_next;
  if (!(std::abs(u_next) > t_lim && u_next * e > 0.0)) integral_ = i_next;
  integral_ = std::clamp(integral_, -t_lim, t_lim);
  const double u = p_term + integral_;
  limited_ = std::abs(u) > t_lim;
  tm_ = std::clamp(u, -t_lim, t_lim);

  // Semi-implicit Euler: viscous term implicit.
  const double J = p_.inertia_kg_m2;
  w_ = (J * w_ + dt * (tm_ - load_torque_N_m)) / (J + dt * p_.viscous_N_m_s);
}

inline double SpindleDrive::rpm() const noexcept {
  return w_ / kRadPerSPerRpm;
}

}  // namespace lathectl::drives
