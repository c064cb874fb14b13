// control::per_revolution_mean: the trailing mean over one revolution at each sample's speed.
// 600 rpm at Δt = 0.01 s is 10 samples a revolution; 1200 rpm is 5.

#include "lathectl/control/per_revolution.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace lathectl::control {
namespace {

TEST(PerRevolutionMean, RemovesAOncePerRevolutionSwing) {
  std::vector<double> x, rpm(200, 600.0);
  for (int i = 0; i < 200; ++i) x.push_back(100.0 + 30.0 * std::sin(2.0 * std::numbers::pi * i / 10.0));
  const auto m = per_revolution_mean(x, rpm, 0.01);
  ASSERT_EQ(m.size(), x.size());
  for (std::size_t i = 9; i < m.size(); ++i) EXPECT_NEAR(m[i], 100.0, 1e-9) << i;
}

TEST(PerRevolutionMean, WindowFollowsTheSpeedBothWays) {
  // 1, 2, 3, ...: the mean of the last w samples ending at i is i + 1 − (w − 1)/2.
  std::vector<double> x, rpm;
  for (int i = 0; i < 60; ++i) {
    x.push_back(i + 1.0);
    rpm.push_back(i < 20 ? 600.0 : i < 40 ? 1200.0 : 600.0);  // 10, 5, then 10 samples again
  }
  const auto m = per_revolution_mean(x, rpm, 0.01);
  EXPECT_DOUBLE_EQ(m[3], 2.5);               // fewer samples than a revolution at the start
  EXPECT_DOUBLE_EQ(m[15], 16.0 - 4.5);       // w = 10
  EXPECT_DOUBLE_EQ(m[30], 31.0 - 2.0);       // w = 5
  EXPECT_DOUBLE_EQ(m[50], 51.0 - 4.5);       // w = 10 again: the window grows back
}

TEST(PerRevolutionMean, AStoppedSpindleCountsAsOneRpm) {
  const std::vector<double> x(10, 7.0), rpm(10, 0.0);
  const auto m = per_revolution_mean(x, rpm, 0.01);
  EXPECT_DOUBLE_EQ(m.back(), 7.0);
}

}  // namespace
}  // namespace lathectl::control
