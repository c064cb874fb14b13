// System A's machine side (include/lathectl/control/slide_machine.hpp): the programming device's
// on/off, mode and setpoint, the laws along the travel, roughing's overload and breakage alarms,
// and the sensor-lost rule (roughing stops, finishing freezes) within one control period.
// The actuator values are checked against the seed's (2)/(3): h = (S·F + K_leak·(P + F_fr)/F)/Ka,
// Ka = μπd·sqrt(2Δp/ρ)·Δt·f.

#include "lathectl/control/slide_machine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::control {
namespace {

using M = SlideMachine;
using Mode = SlideMachine::Mode;

// a_finishing_aim's regulator: d = 5 mm, Δp = 0.2 MPa, ρ = 870, μ = 0.65.
const double kGain = 0.65 * std::numbers::pi * 0.005 * std::sqrt(2.0 * 0.2e6 / 870.0);
constexpr double kF = 8e-4;
constexpr double kLeak = 50e-6 / 60.0 / 1e6;
constexpr double kVperN = 5e-3;
constexpr double kOffset = 0.5;

M::Params params(M::Modulation m, Mode mode) {
  M::Params p;
  auto& c = p.controller;
  c.modulation = m;
  c.mode = mode;
  c.period_s = 1e-3;
  c.regulator_gain_per_m = kGain;
  c.pulse_width_s = 0.005;
  c.frequency_Hz = 20.0;
  c.slot_m = 40e-6;
  c.piston_area_m2 = kF;
  c.leak_m3_per_s_Pa = kLeak;
  c.feed_m_per_s = 1e-3;
  c.force_set_N = 200.0;
  c.sensor_V_per_N = kVperN;
  c.sensor_offset_V = kOffset;
  c.sensor_monitor = {-0.5, 10.5, 0.0, 0.0};
  c.slot_max_m = 1e-4;
  return p;
}

M::Input at(double force_N, Mode mode, double feed = 1e-3, double force_set = 200.0) {
  M::Input in;
  in.sensor_V = kOffset + kVperN * force_N;
  in.mode = mode;
  in.feed_m_per_s = feed;
  in.force_set_N = force_set;
  return in;
}

// (2)-(3): the slot that gives feed S at load P.
double slot_for(double feed, double force) {
  const double ka = kGain * 0.005 * 20.0;
  return (feed * kF + kLeak * force / kF) / ka;
}

TEST(SlideMachine, FinishingFollowsTheSeedsLawAndTheProgrammedFeed) {
  M m;
  m.configure(params(M::Modulation::Amplitude, Mode::Finishing));
  m.start(150.0);
  m.update(at(150.0, Mode::Finishing));
  EXPECT_NEAR(m.output().slot_m, slot_for(1e-3, 150.0), 1e-12);
  EXPECT_TRUE(m.output().pulses);
  // The program doubles the feed: the slot follows (2)-(3) at once.
  m.update(at(150.0, Mode::Finishing, 2e-3));
  EXPECT_NEAR(m.output().slot_m, slot_for(2e-3, 150.0), 1e-12);
  EXPECT_DOUBLE_EQ(m.output().feed_set_m_per_s, 2e-3);
}

TEST(SlideMachine, OffShutsTheValveAndOnStartsBumpless) {
  M m;
  m.configure(params(M::Modulation::Frequency, Mode::Finishing));
  m.start(150.0);
  M::Input in = at(150.0, Mode::Finishing);
  in.enable = false;
  for (int k = 0; k < 500; ++k) m.update(in);  // a resting sensor for 0.5 s: not "stuck"
  EXPECT_FALSE(m.output().pulses);
  EXPECT_EQ(m.output().frequency_Hz, 0.0);
  EXPECT_EQ(m.output().reason, Reason::SlideOff);
  EXPECT_FALSE(m.output().alarm);
  in.enable = true;
  m.update(in);
  EXPECT_TRUE(m.output().pulses);
  EXPECT_FALSE(m.output().alarm);
  EXPECT_NEAR(m.output().frequency_Hz,
              (1e-3 * kF + kLeak * 150.0 / kF) / (kGain * 40e-6 * 0.005), 1e-9);  // (6)
}

TEST(SlideMachine, ModeChangeToRoughingHoldsTheForce) {
  M m;
  m.configure(params(M::Modulation::Amplitude, Mode::Finishing));
  m.start(300.0);
  for (int k = 0; k < 200; ++k) m.update(at(300.0, Mode::Roughing));  // 300 N against 200 N set
  EXPECT_EQ(m.output().mode, Mode::Roughing);
  EXPECT_LT(m.output().feed_cmd_m_per_s, 0.5e-3);  // the regulator lowers the feed
  EXPECT_FALSE(m.output().alarm);                   // 1.5 × 200 = 300 is not above the limit
}

TEST(SlideMachine, FeedLawAlongTheTravel) {
  auto p = params(M::Modulation::Amplitude, Mode::Finishing);
  p.feed_law = {{0.0, 1e-3}, {0.01, 2e-3}};
  EXPECT_DOUBLE_EQ(M::law_at(p.feed_law, -1.0), 1e-3);
  EXPECT_DOUBLE_EQ(M::law_at(p.feed_law, 0.005), 1.5e-3);
  EXPECT_DOUBLE_EQ(M::law_at(p.feed_law, 1.0), 2e-3);
  M m;
  m.configure(p);
  m.start(150.0);
  auto in = at(150.0, Mode::Finishing, 5e-3);  // the law overrides the programmed feed
  in.position_m = 0.0075;
  m.update(in);
  EXPECT_DOUBLE_EQ(m.output().feed_set_m_per_s, 1.75e-3);
  EXPECT_NEAR(m.output().slot_m, slot_for(1.75e-3, 150.0), 1e-12);
}

TEST(SlideMachine, RoughingOverloadStopsTheFeedAfterItsTime) {
  M m;
  m.configure(params(M::Modulation::Amplitude, Mode::Roughing));
  m.start(200.0);
  int k = 0;
  for (; k < 1000 && !m.output().alarm; ++k) m.update(at(320.0, Mode::Roughing));
  // 320 > 1.5·200 from the first sample; the alarm after 50 ms, at the 51st period.
  EXPECT_EQ(k, 51);
  EXPECT_EQ(m.output().alarm_reason, Reason::Overload);
  EXPECT_EQ(m.output().slot_m, 0.0);
  EXPECT_FALSE(m.output().pulses);
  auto in = at(200.0, Mode::Roughing);
  in.reset_alarm = true;
  m.update(in);
  EXPECT_FALSE(m.output().alarm);
  EXPECT_TRUE(m.output().pulses);
}

TEST(SlideMachine, RoughingBreakageOnAForceCollapse) {
  M m;
  m.configure(params(M::Modulation::Frequency, Mode::Roughing));
  m.start(200.0);
  for (int k = 0; k < 50; ++k) m.update(at(200.0, Mode::Roughing));
  EXPECT_FALSE(m.output().alarm);
  m.update(at(40.0, Mode::Roughing));  // 160 N gone in one period: > 0.6 × 200
  EXPECT_TRUE(m.output().alarm);
  EXPECT_EQ(m.output().alarm_reason, Reason::ToolBreakage);
  EXPECT_EQ(m.output().frequency_Hz, 0.0);
}

TEST(SlideMachine, SensorLostWithinOnePeriod) {
  for (auto mode : {Mode::Finishing, Mode::Roughing}) {
    M m;
    m.configure(params(M::Modulation::Amplitude, mode));
    m.start(150.0);
    for (int k = 0; k < 20; ++k) m.update(at(150.0, mode));
    const double slot = m.output().slot_m;
    M::Input in = at(150.0, mode);
    in.sensor_V = std::numeric_limits<double>::quiet_NaN();  // the wire is cut
    m.update(in);                                             // the very next period
    EXPECT_TRUE(m.output().alarm);
    EXPECT_EQ(m.output().alarm_reason, Reason::SensorNotFinite);
    if (mode == Mode::Roughing) {
      EXPECT_EQ(m.output().slot_m, 0.0);
      EXPECT_FALSE(m.output().pulses);
    } else {
      EXPECT_EQ(m.output().slot_m, slot);  // frozen
      EXPECT_TRUE(m.output().pulses);
    }
    in.sensor_V = 20.0;  // out of range after a reset: the same rule
    in.reset_alarm = true;
    m.update(in);
    EXPECT_EQ(m.output().alarm_reason, Reason::SensorOutOfRange);
  }
}

TEST(SlideMachine, ConfigureNamesItsParameter) {
  auto p = params(M::Modulation::Amplitude, Mode::Roughing);
  p.breakage_window_s = 1.0;
  M m;
  try {
    m.configure(p);
    FAIL() << "accepted a 1000-period breakage window";
  } catch (const core::ParameterError& e) {
    EXPECT_EQ(e.parameter(), "breakage_window_s");
  }
  p = params(M::Modulation::Amplitude, Mode::Roughing);
  p.force_law = {{0.01, 100.0}, {0.0, 200.0}};
  try {
    m.configure(p);
    FAIL();
  } catch (const core::ParameterError& e) {
    EXPECT_EQ(e.parameter(), "force_law");
  }
  p = params(M::Modulation::Amplitude, Mode::Roughing);
  p.controller.pulse_width_s = 0.0;
  try {
    m.configure(p);
    FAIL();
  } catch (const core::ParameterError& e) {
    EXPECT_EQ(e.parameter(), "pulse_width_s");
  }
}

}  // namespace
}  // namespace lathectl::control
