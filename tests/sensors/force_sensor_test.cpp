// Lagged, noisy force-parameter sensor (include/lathectl/sensors/force_sensor.hpp).
//
// First-order lag, exact discretisation y ← x + (y − x)·e^(−dt/τ): step response
// y(t) = x·(1 − e^(−t/τ)), y(τ) = 0.632·x (Ogata, "Modern Control Engineering", §5-2).
// Noise: the sample standard deviation of N independent N(0, σ²) draws has a standard error of
// about σ/sqrt(2N) (e.g. NIST/SEMATECH e-Handbook of Statistical Methods, §7.2.4): for
// N = 100000 that is 0.22 % of σ, so a 2 % tolerance is a 9-standard-error bound.

#include "lathectl/sensors/force_sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace lathectl::sensors {
namespace {

LaggedNoisySensor make(const LaggedNoisySensor::Params& p) {
  LaggedNoisySensor s;
  s.configure(p);
  return s;
}

TEST(LaggedNoisySensor, LagReaches63PercentAtTimeConstant) {
  LaggedNoisySensor::Params p;
  p.time_constant_s = 0.002;
  auto s = make(p);
  s.reset(0.0);
  for (int k = 0; k < 200; ++k) s.step(1e-5, 1500.0);  // t = 200·1e−5 = τ
  // 1500·(1 − e^−1) = 948.18 N
  EXPECT_NEAR(s.lagged() / 1500.0, 0.632, 0.01 * 0.632);
  EXPECT_NEAR(s.lagged(), 1500.0 * (1.0 - std::exp(-1.0)), 1e-9);
  EXPECT_DOUBLE_EQ(s.sample(), s.lagged());  // σ = 0: no noise
  // A change of dt midway recomputes the factor: 100 more steps of 2e−5 = another τ.
  for (int k = 0; k < 100; ++k) s.step(2e-5, 1500.0);
  EXPECT_NEAR(s.lagged(), 1500.0 * (1.0 - std::exp(-2.0)), 1e-9);
}

TEST(LaggedNoisySensor, ZeroTimeConstantPassesThrough) {
  LaggedNoisySensor::Params p;
  p.time_constant_s = 0.0;
  auto s = make(p);
  s.step(1e-4, 123.0);
  EXPECT_DOUBLE_EQ(s.lagged(), 123.0);
}

TEST(LaggedNoisySensor, NoiseHasTheConfiguredSigma) {
  LaggedNoisySensor::Params p;
  p.noise_sigma = 2.5;
  p.seed = 42;
  auto s = make(p);
  s.reset(10.0);
  const int n = 100000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double y = s.sample() - 10.0;
    sum += y;
    sum2 += y * y;
  }
  const double mean = sum / n;
  const double sigma = std::sqrt((sum2 - n * mean * mean) / (n - 1));
  EXPECT_NEAR(sigma, 2.5, 0.02 * 2.5);
  EXPECT_NEAR(mean, 0.0, 4.0 * 2.5 / std::sqrt(double(n)));  // 4 standard errors of the mean
}

TEST(LaggedNoisySensor, SaturatesAtRange) {
  LaggedNoisySensor::Params p;
  p.time_constant_s = 0.0;
  p.range = 1000.0;
  p.noise_sigma = 50.0;
  auto s = make(p);
  s.step(1e-4, 5000.0);
  for (int k = 0; k < 1000; ++k) ASSERT_DOUBLE_EQ(s.sample(), 1000.0);
  s.step(1e-4, -5000.0);
  for (int k = 0; k < 1000; ++k) ASSERT_DOUBLE_EQ(s.sample(), -1000.0);
  s.step(1e-4, 990.0);  // near the limit: noise may reach it but never pass it
  bool hit = false;
  for (int k = 0; k < 1000; ++k) {
    const double y = s.sample();
    ASSERT_LE(y, 1000.0);
    hit = hit || y == 1000.0;
  }
  EXPECT_TRUE(hit);
}

TEST(LaggedNoisySensor, SameSeedSameSequence) {
  LaggedNoisySensor::Params p;
  p.noise_sigma = 1.0;
  p.seed = 7;
  auto a = make(p);
  auto b = make(p);
  p.seed = 8;
  auto c = make(p);
  int differ = 0;
  double first = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double ya = a.sample();
    if (k == 0) first = ya;
    ASSERT_EQ(ya, b.sample());
    differ += ya != c.sample();
  }
  EXPECT_GT(differ, 990);
  p.seed = 7;
  a.configure(p);
  EXPECT_EQ(a.sample(), first);  // configure re-seeds: the sequence starts again
}

TEST(LaggedNoisySensor, RejectsBadParameters) {
  LaggedNoisySensor s;
  LaggedNoisySensor::Params p;
  auto bad = p;
  bad.time_constant_s = -1.0;
  EXPECT_THROW(s.configure(bad), std::invalid_argument);
  bad = p;
  bad.noise_sigma = -0.1;
  EXPECT_THROW(s.configure(bad), std::invalid_argument);
  bad = p;
  bad.range = 0.0;
  EXPECT_THROW(s.configure(bad), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::sensors
