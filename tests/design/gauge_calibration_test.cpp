// A gauge from a measured calibration (design/gauge_calibration.hpp): a generated curve with a
// known line, A0 and noise, the line recovered within bounds stated from least squares.
//
// The curve: V = K·(B − x) for x ≤ A0, then flat at K·(B − A0) (the probe's floor), K = 30 mV/µm
// = 3e4 V/m, B = 210 µm, A0 = 200 µm, x = 0, 10, …, 300 µm (31 points), plus normal noise σ = 5
// mV (Box–Muller on mt19937, whose output the standard fixes). Least squares on the 21 points of
// the line: Sxx = 100·Σk² (k = −10…10) = 77 000 µm², σ(slope) = σ/sqrt(Sxx) = 1.8e-5 V/µm
// (0.06 % of K), σ(B) ≈ σ·sqrt(1/21 + 100²/Sxx)/K = 0.07 µm. Beyond A0 the first point is off
// the line by K·10 µm = 0.3 V = 60σ: A0 is found at the grid point 200 µm.
#include "lathectl/design/gauge_calibration.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

namespace {

using lathectl::design::CalibrationPoint;
using lathectl::design::fit_calibration;

std::vector<CalibrationPoint> curve(double sigma_V, std::uint32_t seed) {
  std::mt19937 g(seed);
  auto u = [&] { return (static_cast<double>(g()) + 0.5) / 4294967296.0; };
  std::vector<CalibrationPoint> p;
  for (int k = 0; k <= 30; ++k) {
    const double x = 10e-6 * k;
    const double n =
        sigma_V * std::sqrt(-2.0 * std::log(u())) * std::cos(2.0 * std::numbers::pi * u());
    p.push_back({x, 3e4 * (210e-6 - std::min(x, 200e-6)) + n});
  }
  return p;
}

TEST(GaugeCalibration, RecoversTheLineAndA0WithinTheirBounds) {
  for (std::uint32_t seed : {1u, 2u, 3u, 4u, 5u}) {
    const auto f = fit_calibration(curve(5e-3, seed));
    EXPECT_NEAR(f.free_amplitude_m, 200e-6, 1e-12) << seed;
    EXPECT_EQ(f.points_on_line, 21u) << seed;
    EXPECT_TRUE(f.leaves);
    EXPECT_NEAR(f.gain_V_per_m, 3e4, 3e4 * 5e-3) << seed;  // 8σ of the slope
    EXPECT_NEAR(f.intercept_m, 210e-6, 0.5e-6) << seed;    // 7σ of B
    // The noise and the residual: σ within the spread of an estimate from ~20-30 points.
    EXPECT_GT(f.noise_sigma_V, 0.6 * 5e-3) << seed;
    EXPECT_LT(f.noise_sigma_V, 1.5 * 5e-3) << seed;
    EXPECT_GT(f.residual_sigma_V, 0.6 * 5e-3) << seed;
    EXPECT_LT(f.residual_sigma_V, 1.5 * 5e-3) << seed;
    EXPECT_GT(f.r_squared, 0.9999) << seed;
  }
}

TEST(GaugeCalibration, ExactPointsGiveTheExactLine) {
  const auto f = fit_calibration(curve(0.0, 1));
  EXPECT_NEAR(f.gain_V_per_m, 3e4, 1e-6);
  EXPECT_NEAR(f.intercept_m, 210e-6, 1e-15);
  EXPECT_NEAR(f.free_amplitude_m, 200e-6, 1e-15);
  EXPECT_LT(f.noise_sigma_V, 1e-12);
  EXPECT_NEAR(f.r_squared, 1.0, 1e-12);
  // A curve that never leaves its line: A0 is the last point, and it says so.
  auto line = curve(0.0, 1);
  line.resize(15);
  const auto g = fit_calibration(line);
  EXPECT_FALSE(g.leaves);
  EXPECT_NEAR(g.free_amplitude_m, 140e-6, 1e-15);
}

TEST(GaugeCalibration, RefusesWhatIsNoCalibration) {
  auto p = curve(0.0, 1);
  EXPECT_THROW(fit_calibration(std::span(p).first(4)), std::invalid_argument);
  for (auto& q : p) q.voltage_V = -q.voltage_V;  // rising: no K > 0
  EXPECT_THROW(fit_calibration(p), std::invalid_argument);
  p = curve(0.0, 1);
  std::swap(p[3], p[4]);
  EXPECT_THROW(fit_calibration(p), std::invalid_argument);
}

}  // namespace
