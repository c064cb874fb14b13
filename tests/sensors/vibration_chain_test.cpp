// Seed 001's measurement chain: the amplitude ADC reads a sine's amplitude to one LSB after one
// gate, the frequency detector to its resolution 1/(2·gate); below the dead zone both read 0; a
// static deflection is not vibration (the high-pass). Idle compensation: the seed's stored value
// is right at the stored speed and wrong by P_idle(n₂) − P_idle(n₁) after a speed change; the
// idle table is right at both. An accelerometer's signal integrated to displacement is
// A/(2πf)² through the high-passes' closed-form gain, and an offset neither drifts nor shows.
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

// A real accelerometer (update_acceleration) at a sound interface's 48 kHz.
VibrationChain::Params at_48k() {
  VibrationChain::Params p = quiet();
  p.sample_period_s = 1.0 / 48000.0;
  return p;
}

// The amplitude of sensor_m() at f over `periods` whole periods (projection on sin and cos).
double amplitude(VibrationChain& c, double acc, double f, double offset, int periods, double& t) {
  const double dt = c.params().sample_period_s;
  const auto n = static_cast<int>(std::lround(periods / (f * dt)));
  double s = 0.0, co = 0.0;
  for (int k = 0; k < n; ++k) {
    const double w = 2.0 * std::numbers::pi * f * t;
    c.update_acceleration(offset + acc * std::sin(w));
    s += c.sensor_m() * std::sin(w);
    co += c.sensor_m() * std::cos(w);
    t += dt;
  }
  return 2.0 / n * std::hypot(s, co);
}

TEST(VibrationChain, AccelerationGivesDisplacementAOver2PiFSquaredTimesTheHighPasses) {
  VibrationChain c;
  c.configure(at_48k());
  const double A = 20.0, f = 250.0, fc = 40.0, T = c.params().sample_period_s;
  double t = 0.0;
  (void)amplitude(c, A, f, 0.0, 250, t);  // 1 s: the high-passes' transients die out
  const double got = amplitude(c, A, f, 0.0, 250, t);
  // The analog closed form: A/(2πf)² through two Butterworth high-passes at fc.
  const double g2 = 1.0 / (1.0 + std::pow(fc / f, 4.0));
  EXPECT_NEAR(got / (A / std::pow(2.0 * std::numbers::pi * f, 2.0) * g2), 1.0, 3e-4);
  // The discrete one: prewarped high-passes, trapezoidal integrators.
  const double x = std::numbers::pi * f * T, xc = std::numbers::pi * fc * T;
  const double gd2 = 1.0 / (1.0 + std::pow(std::tan(xc) / std::tan(x), 4.0));
  EXPECT_NEAR(got / (A * std::pow(T / (2.0 * std::tan(x)), 2.0) * gd2), 1.0, 1e-9);
}

TEST(VibrationChain, AnAccelerationOffsetNeitherDriftsNorShows) {
  VibrationChain c, clean;
  c.configure(at_48k());
  clean.configure(at_48k());
  double t = 0.0, t2 = 0.0;
  double worst = 0.0;
  for (int s = 0; s < 60; ++s) {  // a minute with 1 m/s² of DC
    (void)amplitude(c, 20.0, 250.0, 1.0, 250, t);
    worst = std::max(worst, std::abs(c.integrated_m()));
  }
  for (int s = 0; s < 60; ++s) (void)amplitude(clean, 20.0, 250.0, 0.0, 250, t2);
  // The offset is a constant 1/(2π·40 Hz)² = 15.8 µm of displacement before the chain's
  // high-pass (plus the sine's 8 µm), not a growing one; after it, nothing of it is left.
  EXPECT_LT(worst, 16e-6 + 8.2e-6);
  EXPECT_NEAR(amplitude(c, 20.0, 250.0, 1.0, 250, t), amplitude(clean, 20.0, 250.0, 0.0, 250, t2),
              1e-15);
  VibrationChain dc;
  dc.configure(at_48k());
  double t3 = 0.0;
  (void)amplitude(dc, 0.0, 250.0, 1.0, 500, t3);  // 2 s of a pure offset
  EXPECT_LT(std::abs(dc.sensor_m()), 1e-12);
  EXPECT_EQ(dc.a0_m(), 0.0);
  EXPECT_EQ(dc.omega_d(), 0.0);
}

TEST(VibrationChain, AccelerationAndDisplacementOfOneMotionReadAlike) {
  // x = X·sin(ωt) is a = −ω²X·sin(ωt): both chains read a0 within one LSB, ω_d to
  // the detector's resolution.
  VibrationChain from_x, from_a;
  from_x.configure(at_48k());
  from_a.configure(at_48k());
  const double X = 12e-6, w = 2.0 * std::numbers::pi * 226.0, dt = from_x.params().sample_period_s;
  for (int k = 0; k < 48000; ++k) {
    const double t = k * dt;
    from_x.update(X * std::sin(w * t));
    from_a.update_acceleration(-w * w * X * std::sin(w * t));
  }
  EXPECT_NEAR(from_a.a0_m(), from_x.a0_m(), from_x.params().adc_lsb_m);
  EXPECT_GT(from_a.a0_m(), 10e-6);
  // Each to the detector's resolution 1/(2·gate) = 5 Hz (their gates' counts may differ by one).
  EXPECT_NEAR(from_a.omega_d() / (2.0 * std::numbers::pi), 226.0, 5.0);
  EXPECT_NEAR(from_x.omega_d() / (2.0 * std::numbers::pi), 226.0, 5.0);
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
