// Stability lobes, validated layer by layer (system B, part 1).
#include "lathectl/dynamics/lobes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace lathectl::dynamics;

namespace {
// The example mode: k = 2.26e8 N/m, ζ = 0.012, f_n = 250 Hz, θ = 30°, K_f = 1000 N/mm².
ChatterSystem sdof() {
  ChatterSystem s;
  s.kf_N_per_m2 = 1e9;
  s.modes = {{2.26e8, 0.012, 250.0, 30.0 * std::numbers::pi / 180.0}};
  return s;
}
}  // namespace

// Closed form (Altintas, Manufacturing Automation, 2nd ed., eq. 3.30 for SDOF): the minimum of
// −1/(2K_f Re Φ) is b = 2kζ(1+ζ)/(K_f cos²θ) at ω = ω_n√(1+2ζ):
// 2·2.26e8·0.012·1.012/(1e9·0.75) = 7.318784e-3 m, 250·√1.024 = 252.982 Hz.
TEST(Lobes, FrequencyDomainMatchesSdofClosedForm) {
  const auto fd = frequency_domain_lobes(sdof(), 2000, 14000, 40, 20000);
  EXPECT_NEAR(fd.critical_depth_m, 7.318784e-3, 1e-6 * 7.318784e-3);
  EXPECT_NEAR(fd.critical_chatter_Hz, 252.982, 0.05);
  ASSERT_GE(fd.lobes.size(), 5u);
  // Each lobe's minimum lies at n = 60 f_c / (N + ε/2π) with the same depth.
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(fd.lobes[i].minimum.depth_m, 7.318784e-3, 1e-5);
}

TEST(Lobes, SemiDiscretizationAgreesWithFrequencyDomain) {
  const auto s = sdof();
  const auto fd = frequency_domain_lobes(s, 2000, 14000, 40, 8000);
  for (double n : {4000.0, 6500.0, 9500.0, 12000.0}) {
    const double tau = 60.0 / n;
    const int m = static_cast<int>(std::ceil(tau * 250.0 * 25.0));
    const double b_fd = envelope_depth(fd, n);
    const double b_sd = sd_limit_depth(s, n, 3.0 * b_fd, m, 1e-4);
    EXPECT_NEAR(b_sd / b_fd, 1.0, 0.03) << "n = " << n;
  }
}

TEST(Lobes, SpectralRadiusCrossesOneAtTheLimit) {
  const auto s = sdof();
  const double n = 9500.0;
  const double b = sd_limit_depth(s, n, 0.05, 60, 1e-5);
  EXPECT_LT(spectral_radius_sd(s, n, 0.99 * b, 60), 1.0);
  EXPECT_GT(spectral_radius_sd(s, n, 1.01 * b, 60), 1.0);
}

// At the lobe minima the time-domain simulation (with the tool leaving the cut) must decay 3 %
// below the limit and grow 3 % above it.
TEST(Lobes, TimeDomainGrowsAboveAndDecaysBelowAtLobeMinima) {
  const auto s = sdof();
  const auto fd = frequency_domain_lobes(s, 2000, 14000, 40, 20000);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& mn = fd.lobes[i].minimum;
    const auto below = time_domain(s, mn.speed_rpm, 0.97 * mn.depth_m, 0.1e-3, 10.0, 50);
    const auto above = time_domain(s, mn.speed_rpm, 1.03 * mn.depth_m, 0.1e-3, 10.0, 50);
    EXPECT_FALSE(below.grew) << "lobe N = " << fd.lobes[i].N << ": " << below.amplitude_early_m
                             << " → " << below.amplitude_late_m;
    EXPECT_TRUE(above.grew) << "lobe N = " << fd.lobes[i].N << ": " << above.amplitude_early_m
                            << " → " << above.amplitude_late_m;
    EXPECT_LT(below.amplitude_late_m, 0.1 * below.amplitude_early_m);
  }
}

TEST(Lobes, InvalidSystemsAreRejected) {
  ChatterSystem empty;
  EXPECT_THROW(frequency_domain_lobes(empty, 1000, 2000), std::invalid_argument);
  auto s = sdof();
  EXPECT_THROW(frequency_domain_lobes(s, 2000, 1000), std::invalid_argument);
  s.modes[0].damping_ratio = 0.0;
  EXPECT_THROW(frequency_domain_lobes(s, 1000, 2000), std::invalid_argument);
}
