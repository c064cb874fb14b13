// Disturbances of the cutting process (include/lathectl/cutting/disturbances.hpp): deterministic
// profiles checked point by point, the random allowance checked against the statistics of an
// Ornstein–Uhlenbeck process sampled at spacing Δx: variance σ², lag-1 correlation e^(−Δx/L).

#include "lathectl/cutting/disturbances.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace lathectl::cutting {
namespace {

Disturbances make(const DisturbanceParams& p) {
  Disturbances d;
  d.configure(p);
  return d;
}

TEST(Disturbances, NominalDepthWithoutDisturbances) {
  DisturbanceParams p;
  p.depth_mm = 1.5;
  auto d = make(p);
  for (const double x : {0.0, 3.0, 100.0}) {
    const LocalCut c = d.at(x, 1.0, 10.0);
    EXPECT_EQ(c.depth_mm, 1.5);
    EXPECT_EQ(c.strength_factor, 1.0);
    EXPECT_EQ(c.wear_factor, 1.0);
    EXPECT_EQ(c.flank_wear_mm, 0.0);
  }
  EXPECT_EQ(d.first_change_mm(), std::numeric_limits<double>::infinity());
}

TEST(Disturbances, DepthStepsEnteredOverRamp) {
  DisturbanceParams p;
  p.depth_mm = 1.0;
  p.step_ramp_mm = 0.5;
  p.depth_steps = {{10.0, 2.0}, {20.0, 1.5}};
  auto d = make(p);
  // Before the step: nominal. Ramp linear over 0.5 mm: at 10.25 halfway, 1 + (2−1)·0.5 = 1.5.
  EXPECT_DOUBLE_EQ(d.depth_profile(5.0), 1.0);
  EXPECT_DOUBLE_EQ(d.depth_profile(10.0), 1.0);
  EXPECT_NEAR(d.depth_profile(10.1), 1.2, 1e-12);
  EXPECT_DOUBLE_EQ(d.depth_profile(10.25), 1.5);
  EXPECT_DOUBLE_EQ(d.depth_profile(10.5), 2.0);
  EXPECT_DOUBLE_EQ(d.depth_profile(15.0), 2.0);
  // Second step from 2.0 down to 1.5: at 20.25, 2 + (1.5 − 2)·0.5 = 1.75.
  EXPECT_DOUBLE_EQ(d.depth_profile(20.25), 1.75);
  EXPECT_DOUBLE_EQ(d.depth_profile(30.0), 1.5);
  // at() gives the same depth when nothing else varies.
  EXPECT_DOUBLE_EQ(d.at(10.25, 0.0, 0.0).depth_mm, 1.5);
  EXPECT_DOUBLE_EQ(d.first_change_mm(), 10.0);
}

TEST(Disturbances, DepthStepWithoutRampIsImmediate) {
  DisturbanceParams p;
  p.depth_mm = 1.0;
  p.step_ramp_mm = 0.0;
  p.depth_steps = {{10.0, 2.0}};
  auto d = make(p);
  EXPECT_DOUBLE_EQ(d.depth_profile(10.0), 1.0);
  EXPECT_DOUBLE_EQ(d.depth_profile(10.0 + 1e-9), 2.0);
}

TEST(Disturbances, RunoutIsSinusoidalInSpindleAngle) {
  DisturbanceParams p;
  p.depth_mm = 1.0;
  p.runout_mm = 0.03;
  auto d = make(p);
  // depth = profile + runout·sin φ.
  EXPECT_NEAR(d.at(1.0, 0.0, 0.0).depth_mm, 1.0, 1e-15);
  EXPECT_NEAR(d.at(1.0, std::numbers::pi / 2, 0.0).depth_mm, 1.03, 1e-15);
  EXPECT_NEAR(d.at(1.0, 3 * std::numbers::pi / 2, 0.0).depth_mm, 0.97, 1e-15);
  EXPECT_NEAR(d.at(1.0, std::numbers::pi / 6, 0.0).depth_mm, 1.015, 1e-15);  // sin 30° = 0.5
  // The profile alone excludes the runout.
  EXPECT_DOUBLE_EQ(d.depth_profile(1.0), 1.0);
}

TEST(Disturbances, DepthNeverNegative) {
  DisturbanceParams p;
  p.depth_mm = 0.01;
  p.runout_mm = 0.05;
  auto d = make(p);
  EXPECT_EQ(d.at(1.0, 3 * std::numbers::pi / 2, 0.0).depth_mm, 0.0);  // 0.01 − 0.05 → clipped
}

TEST(Disturbances, HardnessInterpolatedLinearly) {
  DisturbanceParams p;
  p.hardness = {{5.0, 1.0}, {15.0, 2.0}, {25.0, 1.5}};
  auto d = make(p);
  EXPECT_DOUBLE_EQ(d.strength_factor(0.0), 1.0);  // before the first point: its value
  EXPECT_DOUBLE_EQ(d.strength_factor(5.0), 1.0);
  EXPECT_DOUBLE_EQ(d.strength_factor(10.0), 1.5);  // 1 + (2−1)·(10−5)/(15−5)
  EXPECT_DOUBLE_EQ(d.strength_factor(12.5), 1.75);
  EXPECT_DOUBLE_EQ(d.strength_factor(15.0), 2.0);
  EXPECT_DOUBLE_EQ(d.strength_factor(20.0), 1.75);  // 2 + (1.5−2)·0.5
  EXPECT_DOUBLE_EQ(d.strength_factor(100.0), 1.5);  // after the last: its value
  EXPECT_DOUBLE_EQ(d.at(10.0, 0.0, 0.0).strength_factor, 1.5);
  EXPECT_DOUBLE_EQ(d.first_change_mm(), 5.0);
}

TEST(Disturbances, FirstChangeIsEarliestOfStepAndHardnessChange) {
  DisturbanceParams p;
  p.depth_steps = {{10.0, 2.0}};
  p.hardness = {{0.0, 1.0}, {8.0, 1.0}, {12.0, 2.0}};  // flat until 8, rising from there
  EXPECT_DOUBLE_EQ(make(p).first_change_mm(), 8.0);
  p.hardness = {{0.0, 1.0}, {14.0, 1.0}, {16.0, 2.0}};
  EXPECT_DOUBLE_EQ(make(p).first_change_mm(), 10.0);
  p.depth_steps.clear();
  EXPECT_DOUBLE_EQ(make(p).first_change_mm(), 14.0);
  p.hardness = {{0.0, 1.3}, {14.0, 1.3}};  // constant: no change
  EXPECT_EQ(make(p).first_change_mm(), std::numeric_limits<double>::infinity());
}

TEST(Disturbances, WearGrowsLinearlyInCutTime) {
  DisturbanceParams p;
  p.wear_VB0_mm = 0.05;
  p.wear_rate_mm_per_min = 0.1;
  p.wear_force_gain_per_mm = 0.5;
  auto d = make(p);
  // VB = VB0 + rate·t/60; wear_factor = 1 + gain·VB.
  LocalCut c = d.at(0.0, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(c.flank_wear_mm, 0.05);
  EXPECT_DOUBLE_EQ(c.wear_factor, 1.025);
  c = d.at(1.0, 0.0, 60.0);  // one minute: VB = 0.15 mm, factor 1.075
  EXPECT_DOUBLE_EQ(c.flank_wear_mm, 0.15);
  EXPECT_DOUBLE_EQ(c.wear_factor, 1.075);
  c = d.at(2.0, 0.0, 300.0);  // five minutes: VB = 0.55, factor 1.275
  EXPECT_NEAR(c.flank_wear_mm, 0.55, 1e-15);
  EXPECT_NEAR(c.wear_factor, 1.275, 1e-15);
}

struct OuStats {
  double mean = 0.0;
  double std = 0.0;
  double lag1 = 0.0;
};

OuStats sample_random_allowance(double sigma, double corr_len, double dx, int n,
                                std::uint64_t seed) {
  DisturbanceParams p;
  p.depth_mm = 100.0;  // far from the zero clip: the random part is depth − 100 exactly
  p.random_sigma_mm = sigma;
  p.random_correlation_mm = corr_len;
  p.seed = seed;
  auto d = make(p);
  std::vector<double> r(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    r[static_cast<std::size_t>(k)] = d.at(dx * k, 0.0, 0.0).depth_mm - 100.0;
  OuStats s;
  for (double v : r) s.mean += v;
  s.mean /= n;
  double var = 0.0, cov = 0.0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    var += (r[k] - s.mean) * (r[k] - s.mean);
    if (k > 0) cov += (r[k] - s.mean) * (r[k - 1] - s.mean);
  }
  s.std = std::sqrt(var / (n - 1));
  s.lag1 = cov / var;
  return s;
}

TEST(Disturbances, RandomAllowanceHasOrnsteinUhlenbeckStatistics) {
  // Exact OU update r ← r·a + σ·sqrt(1 − a²)·N(0,1), a = e^(−Δx/L): stationary variance σ²,
  // lag-1 correlation a. Tolerances: 20000 samples with a ≈ 0.67 give N_eff = N(1−a)/(1+a) ≈ 4000,
  // so the std of the sample std is ≈ σ/sqrt(2 N_eff) ≈ 1.1 % (5 % is > 4 sigma), and the
  // lag-1 estimate scatters by ≈ sqrt((1 − a²)/N) ≈ 0.005 (0.03 is 6 sigma).
  const double sigma = 0.2, L = 5.0;
  for (const double dx : {2.0, 5.0}) {
    for (const std::uint64_t seed : {1ULL, 42ULL, 2024ULL}) {
      const OuStats s = sample_random_allowance(sigma, L, dx, 20000, seed);
      EXPECT_NEAR(s.std, sigma, 0.05 * sigma) << "dx=" << dx << " seed=" << seed;
      EXPECT_NEAR(s.lag1, std::exp(-dx / L), 0.03) << "dx=" << dx << " seed=" << seed;
      EXPECT_NEAR(s.mean, 0.0, 0.02) << "dx=" << dx << " seed=" << seed;  // ≈ 6 σ/√N_eff
    }
  }
}

TEST(Disturbances, RandomAllowanceUncorrelatedAtLongSpacing) {
  // Δx = 10·L: a = e^−10 ≈ 4.5e−5, white in effect.
  const OuStats s = sample_random_allowance(0.1, 1.0, 10.0, 20000, 7);
  EXPECT_NEAR(s.lag1, 0.0, 0.03);
  EXPECT_NEAR(s.std, 0.1, 0.005);
}

TEST(Disturbances, RandomAllowanceDoesNotMoveWhenTravelDoesNot) {
  DisturbanceParams p;
  p.depth_mm = 100.0;
  p.random_sigma_mm = 0.2;
  auto d = make(p);
  const double a = d.at(3.0, 0.0, 0.0).depth_mm;
  EXPECT_EQ(d.at(3.0, 0.0, 0.0).depth_mm, a);  // Δx = 0 → no new draw
  EXPECT_NE(d.at(3.5, 0.0, 0.0).depth_mm, a);
}

TEST(Disturbances, SameSeedSameSequenceOtherSeedOtherSequence) {
  DisturbanceParams p;
  p.depth_mm = 100.0;
  p.random_sigma_mm = 0.2;
  p.random_correlation_mm = 3.0;
  p.seed = 11;
  auto a = make(p);
  auto b = make(p);
  p.seed = 12;
  auto c = make(p);
  int differ = 0;
  for (int k = 0; k < 1000; ++k) {
    const double x = 0.37 * k;
    const double va = a.at(x, 0.0, 0.0).depth_mm;
    EXPECT_EQ(va, b.at(x, 0.0, 0.0).depth_mm);
    if (va != c.at(x, 0.0, 0.0).depth_mm) ++differ;
  }
  EXPECT_GT(differ, 990);
  // Re-configuring restarts the sequence from the seed.
  p.seed = 11;
  a.configure(p);
  auto fresh = make(p);
  for (int k = 0; k < 50; ++k)
    EXPECT_EQ(a.at(0.37 * k, 0.0, 0.0).depth_mm, fresh.at(0.37 * k, 0.0, 0.0).depth_mm);
}

TEST(Disturbances, ConfigureRejectsBadProfiles) {
  Disturbances d;
  DisturbanceParams p;
  p.depth_steps = {{10.0, 2.0}, {5.0, 1.0}};  // descending
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.depth_steps = {{10.0, 2.0}, {10.0, 1.0}};  // equal positions
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.depth_steps = {{5.0, 2.0}, {10.0, 1.0}};
  EXPECT_NO_THROW(d.configure(p));
  p.hardness = {{8.0, 1.0}, {3.0, 2.0}};
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.hardness = {{3.0, 1.0}, {8.0, 0.0}};  // factor must be > 0
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.hardness.clear();
  p.random_sigma_mm = -0.1;
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.random_sigma_mm = 0.1;
  p.random_correlation_mm = 0.0;
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.random_correlation_mm = 5.0;
  p.step_ramp_mm = -1.0;
  EXPECT_THROW(d.configure(p), std::invalid_argument);
  p.step_ramp_mm = 0.5;
  p.wear_rate_mm_per_min = -0.1;
  EXPECT_THROW(d.configure(p), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::cutting
