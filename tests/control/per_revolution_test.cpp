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

// The sample a revolution back (AdaptiveFeedController's trend of the mean): a line is
// interpolated exactly at a fractional window (1300 rpm at 2 ms: 23.08 samples), so the load's
// rise over the revolution, x(t) − x(t − T), is the slope times T whatever the phase; a
// once-per-revolution swing comes back within linear interpolation's Δθ²/8 of its amplitude
// (Δθ = 2π/23.08: 0.93 %).
TEST(PerRevolutionMean, RevolutionAgoInterpolatesAtTheSameAngle) {
  const double dt = 0.002, rpm = 1300.0, T = 60.0 / rpm;
  PerRevolutionMean line(dt, 100.0), swing(dt, 100.0);
  EXPECT_TRUE(std::isnan(line.revolution_ago(rpm)));  // nothing a revolution back yet
  for (int i = 0; i < 200; ++i) {
    const double t = i * dt;
    (void)line.push(3.0 + 5.0 * t, rpm);
    (void)swing.push(100.0 * std::sin(2.0 * std::numbers::pi * t / T), rpm);
    if (i < 25) continue;
    EXPECT_NEAR(3.0 + 5.0 * t - line.revolution_ago(rpm), 5.0 * T, 1e-9) << i;
    EXPECT_NEAR(swing.revolution_ago(rpm), 100.0 * std::sin(2.0 * std::numbers::pi * t / T), 0.93)
        << i;
  }
}

TEST(PerRevolutionMean, AStoppedSpindleCountsAsOneRpm) {
  const std::vector<double> x(10, 7.0), rpm(10, 0.0);
  const auto m = per_revolution_mean(x, rpm, 0.01);
  EXPECT_DOUBLE_EQ(m.back(), 7.0);
}

TEST(PerRevolutionPeak, LeavesOutEachCutsFirstRevolution) {
  // 600 rpm at Δt = 0.01 s: 10 samples a revolution. What the window holds before a cut is not
  // the cut's (here 300 out of the cut: a rapid's reading, a sensor's offset), so a mean ending in
  // a cut's first revolution is not the cut's mean: 300 in air, then cuts at 100 and 150. Each
  // cut's means count from one revolution after contact (t − t_contact > 60/n), whose windows hold
  // the cut only, so the peak is 150, not the 280 of a window with one cut sample.
  PerRevolutionPeak p;
  p.configure(0.01);
  double t = 0.0;
  auto run = [&](int n, double x, bool cutting) {
    for (int i = 0; i < n; ++i, t += 0.01) p.push(t, x, 600.0, cutting);
  };
  run(20, 300.0, false);
  run(10, 100.0, true);  // samples 0 … 9 of the cut: t − t_contact ≤ 0.09 s < 0.1 s
  EXPECT_DOUBLE_EQ(p.peak(), 0.0);
  EXPECT_NEAR(p.since_contact_s(t), 0.10, 1e-12);
  run(30, 100.0, true);
  EXPECT_DOUBLE_EQ(p.peak(), 100.0);
  run(20, 300.0, false);
  EXPECT_DOUBLE_EQ(p.peak(), 100.0);  // air is not a cut
  run(10, 150.0, true);
  EXPECT_DOUBLE_EQ(p.peak(), 100.0);  // the second cut's first revolution, left out
  run(20, 150.0, true);
  EXPECT_DOUBLE_EQ(p.peak(), 150.0);
  EXPECT_DOUBLE_EQ(p.value(), 150.0);
}

// A record's peak (lathectl optimize's prediction and its --verify runs) is PerRevolutionPeak's:
// the same means, each cut's first revolution left out of the peak.
TEST(PerRevolutionPeak, ARecordGivesThePeakOfTheRigsRule) {
  // 600 rpm at 0.01 s: 10 samples a revolution. A cut from sample 20 to 59 whose force is 500 for
  // its first 5 samples (the entry) and 200 after.
  std::vector<double> t, x, rpm(100, 600.0);
  std::vector<unsigned char> cutting;
  for (int i = 0; i < 100; ++i) {
    t.push_back(0.01 * i);
    const bool cut = i >= 20 && i < 60;
    cutting.push_back(cut ? 1 : 0);
    x.push_back(!cut ? 0.0 : i < 25 ? 500.0 : 200.0);
  }
  const auto rec = per_revolution_peak(t, x, rpm, cutting, 0.01);
  PerRevolutionPeak ref;
  ref.configure(0.01);
  ASSERT_EQ(rec.mean.size(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(rec.mean[i], ref.push(t[i], x[i], rpm[i], cutting[i] != 0)) << i;
    EXPECT_EQ(rec.counted[i] != 0, ref.counted()) << i;
  }
  EXPECT_EQ(rec.peak, ref.peak());
  // The entry's revolution is out (its mean, 350 at sample 29, is no cut's mean yet); the first
  // sample past it (31: 0.3 − 0.2 is not > 0.1 in doubles) holds 3 samples of 500 and 7 of 200.
  EXPECT_NEAR(rec.mean[29], 350.0, 1e-9);
  EXPECT_EQ(rec.counted[30], 0);
  EXPECT_EQ(rec.counted[31], 1);
  EXPECT_NEAR(rec.peak, 290.0, 1e-9);
  EXPECT_EQ(rec.counted[60], 0);  // out of the cut
}

}  // namespace
}  // namespace lathectl::control
