// control::adaptive_input: the adaptive controller's Input from measured signals, shared by rig E
// and the LinuxCNC component. Worked values (V = 120 m/min, P_idle = 800 W):
//   Pz 2000 N           → cut power Pz·V/60 = 4000 W, whatever the spindle meter says
//   Py 1000 N, meter 5 kW → 5000 − 800 = 4200 W (not Py·V/60 = 2000 W)
//   power 3000 W        → 3000 W (not 3000·V/60 = 6000 W)
//   not finite          → the meter minus idle; without a meter 0 (no power limit)
// and the speed law's clamp V ≤ V_meas·P_max/P_cut with that power.

#include "lathectl/control/adaptive_input.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lathectl::control {
namespace {

using cutting::ForceParameter;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

AdaptiveSignals signals(double force, double meter_W) {
  AdaptiveSignals s;
  s.force = force;
  s.spindle_power_W = meter_W;
  s.idle_power_W = 800.0;
  s.rpm = 955.0;
  s.speed_m_per_min = 120.0;
  s.feed_rate_mm_per_min = 286.5;
  s.feed_block = true;
  return s;
}

TEST(AdaptiveInput, PassesTheMeasuredSignalsThrough) {
  auto s = signals(2000.0, 5000.0);
  s.feed_block = false;
  const auto in = adaptive_input(ForceParameter::Pz, s);
  EXPECT_EQ(in.force, 2000.0);
  EXPECT_EQ(in.rpm, 955.0);
  EXPECT_EQ(in.speed_m_per_min, 120.0);
  EXPECT_EQ(in.feed_rate_mm_per_min, 286.5);
  EXPECT_FALSE(in.feed_block);
}

TEST(AdaptiveInput, PzGivesPzTimesSpeed) {
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Pz, signals(2000.0, 5000.0)).cut_power_W,
                   4000.0);
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Pz, signals(2000.0, kNaN)).cut_power_W, 4000.0);
  // A lost dynamometer: the meter minus the idle power.
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Pz, signals(kNaN, 5000.0)).cut_power_W, 4200.0);
}

TEST(AdaptiveInput, PyGivesTheMeterMinusIdleNotForceTimesSpeed) {
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Py, signals(1000.0, 5000.0)).cut_power_W,
                   4200.0);
  EXPECT_EQ(adaptive_input(ForceParameter::Py, signals(1000.0, kNaN)).cut_power_W, 0.0);
}

TEST(AdaptiveInput, PowerSensorIsTheCutPower) {
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Power, signals(3000.0, 5000.0)).cut_power_W,
                   3000.0);
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Power, signals(3000.0, kNaN)).cut_power_W,
                   3000.0);
  EXPECT_DOUBLE_EQ(adaptive_input(ForceParameter::Power, signals(kNaN, 5000.0)).cut_power_W,
                   4200.0);
}

TEST(AdaptiveInput, NeverNegative) {
  EXPECT_EQ(adaptive_input(ForceParameter::Pz, signals(-50.0, 5000.0)).cut_power_W, 0.0);
  EXPECT_EQ(adaptive_input(ForceParameter::Power, signals(-50.0, 5000.0)).cut_power_W, 0.0);
  EXPECT_EQ(adaptive_input(ForceParameter::Py, signals(1000.0, 300.0)).cut_power_W, 0.0);
}

// The speed law's power clamp with a power sensor: V_cmd → V·P_max/P_cut = 120·2400/3000 = 96.
TEST(AdaptiveInput, PowerSensorDrivesTheSpeedLawsPowerLimit) {
  AdaptiveFeedController::Params p;
  p.mode = AdaptiveFeedController::Mode::ForceFeedSpeed;
  p.load_limit = 4000.0;  // W
  p.feed_programmed_mm_per_rev = 0.3;
  p.feed_planned_mm_per_rev = 0.3;
  p.speed_programmed_m_per_min = 120.0;
  p.cut_power_max_W = 2400.0;
  p.sensor_monitor = {-800.0, 20000.0, 0.0, 0.0};
  AdaptiveFeedController c;
  c.configure(p);
  AdaptiveFeedController::Output out;
  for (int k = 0; k < 2000; ++k) {  // 4 s: the speed ramp (100 m/min/s) has long settled
    auto s = signals(3000.0 + 10.0 * std::sin(0.7 * k), 5000.0);
    s.feed_rate_mm_per_min = 0.3 * s.rpm;  // the measured feed is S_p: V_opt = V_p
    c.update(adaptive_input(ForceParameter::Power, s), out);
  }
  EXPECT_NEAR(out.speed_m_per_min, 96.0, 0.5);
  EXPECT_NEAR(out.rpm, 955.0 * 96.0 / 120.0, 4.0);
}

}  // namespace
}  // namespace lathectl::control
