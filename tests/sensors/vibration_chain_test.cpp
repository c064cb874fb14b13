// Seed 001's measurement chain: the amplitude ADC reads a sine's amplitude to one LSB after one
// gate, the frequency detector to its resolution 1/(2·gate); below the dead zone both read 0; a
// static deflection is not vibration (the high-pass). Idle compensation: the seed's stored value
// is right at the stored speed and wrong by P_idle(n₂) − P_idle(n₁) after a speed change; the
// idle table is right at both.
#include "lathectl/sensors/vibration_chain.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace lathectl::sensors {
namespace {

VibrationChain::Params quiet() {
  VibrationChain::Params p;
  p.noise_m = 0.0;
  return p;
}

void feed(VibrationChain& c, double amp, double f, double seconds, double offset = 0.0) {
  const auto n = static_cast<int>(seconds / c.params().sample_period_s);
  static double t = 0.0;
  for (int k = 0; k < n; ++k) {
    c.update(offset + amp * std::sin(2.0 * std::numbers::pi * f * t));
    t += c.params().sample_period_s;
  }
}

TEST(VibrationChain, ReadsAmplitudeAndFrequencyToTheirResolution) {
  VibrationChain c;
  c.configure(quiet());
  feed(c, 20e-6, 230.0, 0.5);
  EXPECT_LE(c.a0_m(), 20e-6);
  EXPECT_GT(c.a0_m(), 20e-6 - 1.5e-6);  // one ADC LSB (1 µm) plus the sampled peak
  const double res = 1.0 / (2.0 * c.params().frequency_gate_s);
  EXPECT_NEAR(c.omega_d() / (2.0 * std::numbers::pi), 230.0, res);
}

TEST(VibrationChain, PublishesOnlyAtTheGatesEnd) {
  VibrationChain c;
  c.configure(quiet());
  feed(c, 20e-6, 230.0, 0.5 * c.params().amplitude_gate_s);
  EXPECT_EQ(c.a0_m(), 0.0);  // the first gate has not ended
  feed(c, 20e-6, 230.0, 0.6 * c.params().amplitude_gate_s);
  EXPECT_GT(c.a0_m(), 0.0);
}

TEST(VibrationChain, BelowTheDeadZoneBothOutputsAreZero) {
  VibrationChain c;
  c.configure(quiet());
  feed(c, 3e-6, 230.0, 0.5);  // dead zone 5 µm
  EXPECT_EQ(c.a0_m(), 0.0);
  EXPECT_EQ(c.omega_d(), 0.0);
  EXPECT_EQ(c.amplifier_m(), 0.0);
}

TEST(VibrationChain, StaticDeflectionIsNotVibration) {
  VibrationChain c;
  c.configure(quiet());
  feed(c, 0.0, 230.0, 0.5, 50e-6);  // a 50 µm step of the part's bending
  EXPECT_EQ(c.a0_m(), 0.0);
}

TEST(PowerSensor, SeedsStoredIdleIsRightOnlyAtItsSpeed) {
  const auto idle = [](double n) { return 300.0 + 0.3 * n + 1e-4 * n * n; };
  PowerSensor::Params p;
  p.meter.noise_sigma = 0.0;
  PowerSensor seed, table;
  seed.configure(p, 1e-3);
  p.idle_table_rpm = {0.0, 500.0, 800.0, 1200.0, 2000.0};
  for (double n : p.idle_table_rpm) p.idle_table_W.push_back(idle(n));
  table.configure(p, 1e-3);
  for (int k = 0; k < 1000; ++k) {  // idle block at 800 rpm
    seed.update(idle(800.0), 800.0, true);
    table.update(idle(800.0), 800.0, true);
  }
  for (int k = 0; k < 1000; ++k) {  // cutting 2 kW at 800 rpm
    seed.update(idle(800.0) + 2000.0, 800.0, false);
    table.update(idle(800.0) + 2000.0, 800.0, false);
  }
  EXPECT_NEAR(seed.cutting_W(), 2000.0, 2.0);
  EXPECT_NEAR(table.cutting_W(), 2000.0, 2.0);
  EXPECT_DOUBLE_EQ(seed.idle_stored_rpm(), 800.0);
  for (int k = 0; k < 1000; ++k) {  // same cut at 1200 rpm
    seed.update(idle(1200.0) + 2000.0, 1200.0, false);
    table.update(idle(1200.0) + 2000.0, 1200.0, false);
  }
  EXPECT_NEAR(seed.cutting_W(), 2000.0 + idle(1200.0) - idle(800.0), 2.0);
  EXPECT_NEAR(table.cutting_W(), 2000.0, 2.0);
}

TEST(PowerSensor, RejectsBadTables) {
  PowerSensor s;
  PowerSensor::Params p;
  p.idle_table_rpm = {100.0, 50.0};
  p.idle_table_W = {1.0, 2.0};
  EXPECT_THROW(s.configure(p, 1e-3), std::invalid_argument);
  p.idle_table_W = {1.0};
  EXPECT_THROW(s.configure(p, 1e-3), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::sensors
