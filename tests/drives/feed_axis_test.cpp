// CNC feed axis (include/lathectl/drives/feed_axis.hpp) against closed forms.
//
// First-order velocity loop v̇ = (v_ref − v)/τ from rest, step v_ref (any control text, e.g.
// Ogata, "Modern Control Engineering", 5th ed., §5-2, first-order systems):
//   v(t) = v_ref·(1 − e^(−t/τ)),  v(τ) = 0.632·v_ref
//   z(t) = v_ref·(t − τ·(1 − e^(−t/τ)))
// Acceleration-limited start (constant acceleration a): v = a·t, z = a·t²/2.
// Encoder: position quantised to the resolution q, velocity = Δz_quantised / window, so the
// measured velocity is a whole multiple of q/window and is exact when the window's travel is a
// whole number of counts (and no position sits on a rounding tie).

#include "lathectl/drives/feed_axis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::drives {
namespace {

constexpr double kDt = 1e-4;

FeedAxis make(const FeedAxis::Params& p, double dt = kDt) {
  FeedAxis a;
  a.configure(p, dt);
  return a;
}

TEST(FeedAxis, StepResponseReaches63PercentAtTimeConstant) {
  FeedAxis::Params p;
  p.time_constant_s = 0.01;
  p.max_acceleration_m_per_s2 = 100.0;  // v_ref/τ = 5 m/s² at the start: the limit stays out
  auto ax = make(p);
  const double v_ref = 0.05;
  for (int k = 0; k < 100; ++k) ax.step(v_ref);  // t = 100·1e−4 = τ
  // v(τ)/v_ref = 1 − e^−1 = 0.632121
  EXPECT_NEAR(ax.velocity_m_per_s() / v_ref, 0.632, 0.01 * 0.632);
  EXPECT_NEAR(ax.velocity_m_per_s(), v_ref * (1.0 - std::exp(-1.0)),
              1e-12);  // exact discretisation
  // z(τ) = 0.05·(0.01 − 0.01·0.632121) = 1.839397e−4 m (trapezoidal position, O(dt²) error)
  EXPECT_NEAR(ax.position_m(), 1.839397e-4, 1e-4 * 1.839397e-4);
}

TEST(FeedAxis, AccelerationLimitGivesConstantSlope) {
  FeedAxis::Params p;
  p.time_constant_s = 0.01;
  p.max_acceleration_m_per_s2 = 2.0;
  p.max_velocity_m_per_s = 0.1;
  auto ax = make(p);
  // Unlimited, the lag would start at (0.1 − 0)/0.01 = 10 m/s²; the limit binds while
  // (0.1 − v)/τ > 2, i.e. up to v ≈ 0.08 m/s, t ≈ 0.04 s.
  for (int k = 1; k <= 200; ++k) {
    const double v_before = ax.velocity_m_per_s();
    ax.step(0.1);
    ASSERT_NEAR((ax.velocity_m_per_s() - v_before) / kDt, 2.0, 1e-8) << "step " << k;
  }
  // t = 0.02 s: v = 2·0.02 = 0.04 m/s, z = 2·0.02²/2 = 4e−4 m
  EXPECT_NEAR(ax.velocity_m_per_s(), 0.04, 1e-12);
  EXPECT_NEAR(ax.position_m(), 4e-4, 1e-12);
  for (int k = 0; k < 5000; ++k) ax.step(0.1);
  EXPECT_NEAR(ax.velocity_m_per_s(), 0.1, 1e-12);
}

TEST(FeedAxis, VelocityIsLimitedToRapidTraverse) {
  FeedAxis::Params p;
  p.max_velocity_m_per_s = 0.1;
  auto ax = make(p);
  double v_peak = 0.0;
  for (int k = 0; k < 10000; ++k) {
    ax.step(0.5);
    v_peak = std::max(v_peak, ax.velocity_m_per_s());
  }
  EXPECT_LE(v_peak, 0.1);
  EXPECT_NEAR(ax.velocity_m_per_s(), 0.1, 1e-12);
  for (int k = 0; k < 20000; ++k) ax.step(-0.5);
  EXPECT_NEAR(ax.velocity_m_per_s(), -0.1, 1e-12);
}

TEST(FeedAxis, EncoderQuantisesMeasuredVelocity) {
  FeedAxis::Params p;
  p.encoder_resolution_m = 1e-6;
  p.velocity_window_s = 0.01;  // 100 steps; velocity quantum q/window = 1e−4 m/s
  auto ax = make(p);
  // Creep at 1e−5 m/s: 0.1 count per window, below one quantum. The display reads 0 or 1e−4,
  // and the mean over 10 s is the true speed within one count over the run (1e−6/10 = 1e−7).
  ax.reset(0.25e-6, 1e-5);
  double sum = 0.0;
  int nonzero = 0;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    ax.step(1e-5);
    const double counts = ax.measured_velocity_m_per_s() * 0.01 / 1e-6;
    ASSERT_NEAR(counts, std::round(counts), 1e-6) << "not a whole number of counts at " << k;
    ASSERT_TRUE(std::round(counts) == 0.0 || std::round(counts) == 1.0) << counts;
    nonzero += std::round(counts) != 0.0;
    sum += ax.measured_velocity_m_per_s();
  }
  EXPECT_GT(nonzero, 0);
  EXPECT_NEAR(sum / n, 1e-5, 2e-7);
}

TEST(FeedAxis, MeasuredVelocityEqualsTrueInSteadyMotion) {
  FeedAxis::Params p;
  p.encoder_resolution_m = 1e-6;
  p.velocity_window_s = 0.01;
  auto ax = make(p);
  // 0.005 m/s (300 mm/min): 0.5 µm per step, 50 counts per window; positions at .25/.75 µm
  // offsets, never on a rounding tie → measured = 50e−6/0.01 = 0.005 m/s exactly.
  ax.reset(0.25e-6, 0.005);
  EXPECT_DOUBLE_EQ(ax.measured_velocity_m_per_s(), 0.005);
  for (int k = 0; k < 1000; ++k) {
    ax.step(0.005);
    ASSERT_NEAR(ax.measured_velocity_m_per_s(), 0.005, 1e-12) << "step " << k;
  }
  // Any steady speed: within one quantum (1e−6/0.01 = 1e−4 m/s) from the first step on, because
  // reset() filled the history with the steady motion.
  ax.reset(0.0123, 0.0123);
  EXPECT_DOUBLE_EQ(ax.measured_velocity_m_per_s(), 0.0123);
  for (int k = 0; k < 1000; ++k) {
    ax.step(0.0123);
    ASSERT_LE(std::abs(ax.measured_velocity_m_per_s() - 0.0123), 1e-4 + 1e-12) << "step " << k;
    ASSERT_DOUBLE_EQ(ax.velocity_m_per_s(), 0.0123);
  }
}

TEST(FeedAxis, WindowShorterThanStepUsesOneStep) {
  FeedAxis::Params p;
  p.encoder_resolution_m = 1e-6;
  p.velocity_window_s = 1e-5;  // < dt: one-step difference
  auto ax = make(p);
  ax.reset(0.25e-6, 0.01);  // 1 µm per step
  ax.step(0.01);
  EXPECT_NEAR(ax.measured_velocity_m_per_s(), 0.01, 1e-12);
}

TEST(FeedAxis, RejectsBadParameters) {
  FeedAxis ax;
  FeedAxis::Params p;
  EXPECT_THROW(ax.configure(p, 0.0), std::invalid_argument);
  auto bad = p;
  bad.time_constant_s = -1.0;
  EXPECT_THROW(ax.configure(bad, kDt), std::invalid_argument);
  bad = p;
  bad.max_velocity_m_per_s = 0.0;
  EXPECT_THROW(ax.configure(bad, kDt), std::invalid_argument);
  bad = p;
  bad.max_acceleration_m_per_s2 = -2.0;
  EXPECT_THROW(ax.configure(bad, kDt), std::invalid_argument);
  bad = p;
  bad.encoder_resolution_m = 0.0;
  EXPECT_THROW(ax.configure(bad, kDt), std::invalid_argument);
  bad = p;
  bad.velocity_window_s = std::nan("");
  EXPECT_THROW(ax.configure(bad, kDt), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::drives
