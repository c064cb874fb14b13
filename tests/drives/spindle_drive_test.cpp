// Spindle drive (include/lathectl/drives/spindle_drive.hpp) against closed forms.
//
// Default parameters: J = 0.5 kg·m², b = 0.01 N·m·s, T_max = 400 N·m, P_max = 15 kW, η = 0.85,
// P_idle = 300 + 0.3·n + 1e−4·n² W, kp = 20 N·m·s, Ti = 0.05 s, ramp 2000 rpm/s.
// Base speed ω_base = P_max/T_max = 15000/400 = 37.5 rad/s (358.1 rpm).
// Closed forms used:
// - PI speed loop on J·ω̇ = T − T_load − b·ω: integral action → zero steady error under a
//   constant load; steady torque T_m = T_load + b·ω (torque balance).
// - At the torque limit: ω̇ = (T_max − T_load − b·ω)/J (Newton's second law, rotation).
// - Constant-power range (ω > ω_base): T ≤ P_max/ω (drive data-sheet torque–speed curve, e.g.
//   Siemens SINAMICS / any spindle motor's S1 characteristic).
// - Electrical power: P_el = T_m·ω/η + P_idle(n).
// Loop check: J·s² + kp·s + kp/Ti = 0 → s² + 40 s + 800, ω_n = 28.3 rad/s, ζ = 0.71.

#include "lathectl/drives/spindle_drive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::drives {
namespace {

constexpr double kDt = 1e-4;
constexpr double kRadPerRpm = 2.0 * std::numbers::pi / 60.0;

SpindleDrive make(const SpindleDrive::Params& p = {}) {
  SpindleDrive d;
  d.configure(p);
  return d;
}

void run(SpindleDrive& d, double seconds, double rpm_cmd, double load, double dt = kDt) {
  const long n = std::lround(seconds / dt);
  for (long k = 0; k < n; ++k) d.step(dt, rpm_cmd, load);
}

TEST(SpindleDrive, ResetIsSteadyWithoutLoad) {
  auto d = make();
  d.reset(1000.0);
  run(d, 0.5, 1000.0, 0.0);
  EXPECT_NEAR(d.rpm(), 1000.0, 1e-9);
  EXPECT_NEAR(d.motor_torque_N_m(), 0.01 * 1000.0 * kRadPerRpm, 1e-9);  // b·ω = 1.0472 N·m
}

TEST(SpindleDrive, PiHoldsSpeedUnderLoadWithZeroSteadyError) {
  auto d = make();
  d.reset(1000.0);
  double rpm_min = 1e9;
  for (int k = 0; k < 20000; ++k) {
    d.step(kDt, 1000.0, 100.0);
    rpm_min = std::min(rpm_min, d.rpm());
  }
  EXPECT_LT(rpm_min, 995.0);  // the load step is felt …
  EXPECT_GT(rpm_min, 950.0);
  EXPECT_NEAR(d.rpm(), 1000.0, 1e-6);  // … and integral action removes it
  // T_m = T_load + b·ω = 100 + 0.01·104.719755 = 101.047198 N·m
  EXPECT_NEAR(d.motor_torque_N_m(), 101.047198, 1e-6);
  EXPECT_FALSE(d.torque_limited());
}

TEST(SpindleDrive, TorqueLimitCapsAcceleration) {
  SpindleDrive::Params p;
  p.viscous_N_m_s = 0.0;  // ω̇ = (T_max − T_load)/J exactly
  p.max_accel_rpm_per_s = 1e9;
  auto d = make(p);
  d.reset(100.0);  // ω0 = 10.471976 rad/s, below ω_base = 37.5
  for (int k = 0; k < 300; ++k) {
    const double w0 = d.omega();
    d.step(kDt, 2000.0, 50.0);
    ASSERT_TRUE(d.torque_limited()) << "step " << k;
    ASSERT_DOUBLE_EQ(d.motor_torque_N_m(), 400.0);
    // ω̇ = (400 − 50)/0.5 = 700 rad/s²
    ASSERT_NEAR((d.omega() - w0) / kDt, 700.0, 1e-6) << "step " << k;
  }
  // t = 0.03 s: ω = 10.471976 + 700·0.03 = 31.471976 rad/s
  EXPECT_NEAR(d.omega(), 31.471976, 1e-6);
}

TEST(SpindleDrive, PowerLimitAboveBaseSpeed) {
  SpindleDrive::Params p;
  p.max_accel_rpm_per_s = 1e9;
  auto d = make(p);
  d.reset(1000.0);  // 104.7 rad/s > ω_base: T_lim = 15000/104.7 = 143.2 N·m < T_max
  int limited = 0;
  double rpm_peak = 0.0;
  for (int k = 0; k < 50000; ++k) {
    const double w0 = d.omega();
    d.step(kDt, 3000.0, 20.0);
    ASSERT_LE(d.motor_torque_N_m(), 15000.0 / w0 + 1e-9) << "step " << k;
    if (d.torque_limited()) {
      ++limited;
      ASSERT_NEAR(d.motor_torque_N_m() * w0, 15000.0, 1e-6);  // at the power limit, exactly
    }
    rpm_peak = std::max(rpm_peak, d.rpm());
  }
  EXPECT_GT(limited, 5000);  // 1000 → 3000 rpm at ≤ 15 kW takes well over 0.5 s
  EXPECT_NEAR(d.rpm(), 3000.0, 1e-3);
  // Anti-windup: after ~1 s saturated the overshoot stays small (a winding integral would add
  // tens of thousands of N·m·s and overshoot by hundreds of rpm).
  EXPECT_LT(rpm_peak, 3000.0 * 1.01);
}

TEST(SpindleDrive, ElectricalPowerInSteadyCut) {
  auto d = make();
  d.reset(1000.0);
  run(d, 2.0, 1000.0, 100.0);
  // ω = 104.719755 rad/s, T_m = 101.047198 N·m, T_m·ω = 10581.638 W, /0.85 = 12448.986 W;
  // P_idle(1000) = 300 + 0.3·1000 + 1e−4·1000² = 700 W → P_el = 13148.986 W
  EXPECT_NEAR(d.idle_power_W(1000.0), 700.0, 1e-12);
  EXPECT_NEAR(d.electrical_power_W(), 13148.986, 1e-3);
}

TEST(SpindleDrive, BrakingReturnsEfficiencyTimesMechanicalPower) {
  auto d = make();
  d.reset(2000.0);
  run(d, 0.1, 500.0, 0.0);
  ASSERT_LT(d.motor_torque_N_m(), 0.0);  // decelerating: the motor brakes
  const double mech = d.motor_torque_N_m() * d.omega();
  EXPECT_NEAR(d.electrical_power_W(), 0.85 * mech + d.idle_power_W(d.rpm()), 1e-9);
  EXPECT_LT(d.electrical_power_W(), d.idle_power_W(d.rpm()));
}

TEST(SpindleDrive, CommandRampLimitsAcceleration) {
  auto d = make();  // ramp 2000 rpm/s
  d.reset(200.0);
  // 200 → 1000 rpm takes 0.4 s on the ramp. Unramped, the torque limit would allow
  // 400/0.5 = 800 rad/s² = 7640 rpm/s (and ≥ 2735 rpm/s at the power limit up to 1000 rpm),
  // reaching 1000 rpm in about 0.15 s.
  // PI + inertia is type 2: it follows the ramp with vanishing lag once the start transient
  // (1/(ζ·ω_n) = 0.05 s) has passed; from 0.15 s to the ramp's end at 0.4 s the speed stays
  // within 5 rpm of the ramp 200 + 2000·t.
  for (int k = 1; k <= 4000; ++k) {
    d.step(kDt, 1000.0, 0.0);
    const double t = k * kDt;
    if (t >= 0.15) {
      ASSERT_NEAR(d.rpm(), 200.0 + 2000.0 * t, 5.0) << "t = " << t;
    }
  }
  run(d, 1.0, 1000.0, 0.0);
  EXPECT_NEAR(d.rpm(), 1000.0, 0.01);
}

TEST(SpindleDrive, CommandClampedToSpeedRange) {
  auto d = make();
  d.reset(1000.0);
  run(d, 10.0, 1e5, 0.0, 1e-3);
  EXPECT_NEAR(d.rpm(), 4000.0, 1e-3);  // max_rpm
  run(d, 10.0, 0.0, 0.0, 1e-3);
  EXPECT_NEAR(d.rpm(), 10.0, 1e-3);  // min_rpm
}

TEST(SpindleDrive, RejectsBadParameters) {
  SpindleDrive d;
  SpindleDrive::Params p;
  auto bad = p;
  bad.inertia_kg_m2 = 0.0;
  EXPECT_THROW(d.configure(bad), std::invalid_argument);
  bad = p;
  bad.efficiency = 1.2;
  EXPECT_THROW(d.configure(bad), std::invalid_argument);
  bad = p;
  bad.ti_s = 0.0;
  EXPECT_THROW(d.configure(bad), std::invalid_argument);
  bad = p;
  bad.min_rpm = 5000.0;
  EXPECT_THROW(d.configure(bad), std::invalid_argument);
  bad = p;
  bad.max_power_W = -1.0;
  EXPECT_THROW(d.configure(bad), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::drives
