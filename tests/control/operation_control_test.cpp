// lathectl_adaptive's shop blocks (control/operation_control): the idle tare against seed 001's
// idle law, teach-in against a load whose steady mean is known, the operation record, the setting
// checks, and AdaptiveFeedController::set_operation.

#include "lathectl/control/operation_control.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "lathectl/control/adaptive_feed_controller.hpp"

namespace {

using lathectl::control::AdaptiveFeedController;
using lathectl::control::IdleTare;
using lathectl::control::OperationStats;
using lathectl::control::PathBreakage;
using lathectl::control::SettingError;
using lathectl::control::TeachIn;

// Seed 001's idle law P_idle(n) = p0 + p1·n + p2·n² (drives::idle_power_W), its default values.
double law(double n) { return 300.0 + 0.3 * n + 1e-4 * n * n; }

// The spindle dwells at each speed for `dwell_s` (a 0.3 s ramp between), out of the cut.
void sweep(IdleTare& t, std::initializer_list<double> speeds, double dwell_s, double scale = 1.0) {
  double n = 0.0;
  for (double target : speeds) {
    const double n0 = n;
    for (double s = 0.0; s < 0.3; s += 0.002) {  // a ramp: the drive's acceleration power too
      n = n0 + (target - n0) * s / 0.3;
      t.update(n, scale * law(n) + 5000.0, 0.002, true);
    }
    n = target;
    for (double s = 0.0; s < dwell_s; s += 0.002) t.update(n, scale * law(n), 0.002, true);
  }
}

TEST(IdleTare, LearnsTheQuadraticLawFromThreeSpeeds) {
  IdleTare t;
  t.configure({});
  EXPECT_TRUE(std::isnan(t.idle_W(1000.0)));
  sweep(t, {400.0, 1600.0, 2800.0}, 1.0);
  ASSERT_TRUE(t.ready());
  // Exact law, exact samples: the least-squares fit is the law (the ramps' 5 kW of acceleration
  // power was never learned: the speed was changing).
  for (double n = 100.0; n <= 3000.0; n += 100.0) EXPECT_NEAR(t.idle_W(n), law(n), 1e-6 * law(n));
  const auto c = t.coefficients();
  EXPECT_NEAR(c[0], 300.0, 1e-6);
  EXPECT_NEAR(c[1], 0.3, 1e-9);
  EXPECT_NEAR(c[2], 1e-4, 1e-12);
  EXPECT_TRUE(t.covers(1000.0));
  EXPECT_FALSE(t.covers(3900.0));
}

TEST(IdleTare, NothingLearnedInTheCutOrWhileAccelerating) {
  IdleTare t;
  t.configure({});
  for (int k = 0; k < 1000; ++k) t.update(1000.0, 9000.0, 0.002, false);  // cutting
  for (int k = 0; k < 1000; ++k) t.update(100.0 + k, law(100.0 + k), 0.002, true);  // 500 rpm/s
  EXPECT_EQ(t.bins_learned(), 0u);
  EXPECT_FALSE(t.covers(1000.0));
}

TEST(IdleTare, FollowsWarmUpDrift) {
  IdleTare t;
  t.configure({});  // tau 3 s
  sweep(t, {400.0, 1600.0, 2800.0}, 1.0, 1.15);  // cold: 15 % more
  sweep(t, {400.0, 1600.0, 2800.0}, 15.0);       // warm: 5 time constants at each speed
  for (double n : {500.0, 1200.0, 2500.0}) EXPECT_NEAR(t.idle_W(n), law(n), 0.002 * law(n));
}

TEST(TeachIn, ReferenceIsTheSteadyMeanWithoutEntryAndExit) {
  TeachIn t;
  t.configure({});
  t.start();
  const double rpm = 1200.0, dt = 0.001;  // 50 samples per revolution
  double ref = 0.0;
  bool done = false;
  auto step = [&](double load, bool in_cut) {
    if (t.sample(load, rpm, dt, in_cut)) {
      done = true;
      ref = t.reference();
    }
  };
  for (int k = 0; k < 300; ++k) step(1000.0 * k / 300.0, true);  // entry: 6 revolutions
  for (int k = 0; k < 2500; ++k)  // steady: 50 revolutions, a ripple of whole revolutions
    step(1000.0 + 80.0 * std::sin(2.0 * M_PI * k / 50.0), true);
  for (int k = 0; k < 200; ++k) step(1000.0 * (1.0 - k / 200.0), true);  // exit: 4 revolutions
  EXPECT_FALSE(done);  // still in the cut
  step(0.0, false);
  ASSERT_TRUE(done);
  EXPECT_NEAR(ref, 1000.0, 1.0);  // the steady mean; the ramps would pull it below 990
  EXPECT_GE(t.revolutions(), 40.0);
  EXPECT_FALSE(t.running());
}

TEST(TeachIn, TooShortACutTeachesNothing) {
  TeachIn t;
  t.configure({});
  t.start();
  bool done = false;
  for (int k = 0; k < 200; ++k) done |= t.sample(1000.0, 1200.0, 0.001, true);
  done |= t.sample(0.0, 1200.0, 0.001, false);
  EXPECT_FALSE(done);
  EXPECT_TRUE(t.running());  // waits for the next cut
}

TEST(OperationStats, PerRevolutionMeanPeakAndFeed) {
  // The per-revolution mean comes from the one PerRevolutionMean (0.001 s samples at 600 rpm:
  // 100 a revolution); the peak counts only whole revolutions.
  OperationStats s;
  lathectl::control::PerRevolutionMean rev(0.001, 10.0);
  for (int k = 0; k < 100; ++k) s.sample(0.0, 0.0, false, 1.0, 0.001, false);  // approach
  for (int k = 0; k < 1000; ++k) {  // 10 revolutions at 600 rpm: 800 N then 1200 N
    const double load = k < 500 ? 800.0 : 1200.0;
    const double m = rev.push(k == 0 ? 5000.0 : load, 600.0);  // an entry spike: no whole rev
    s.sample(load, m, rev.full(), k < 500 ? 1.0 : 0.5, 0.001, true);
  }
  EXPECT_NEAR(s.mean_load(), 1000.0, 1e-9);
  EXPECT_NEAR(s.peak_load(), 1200.0, 1e-9);
  EXPECT_NEAR(s.feed_min(), 0.5, 1e-12);
  EXPECT_NEAR(s.feed_mean(), 0.75, 1e-12);
  EXPECT_NEAR(s.time_in_cut_s(), 1.0, 1e-9);
  EXPECT_NEAR(s.time_s(), 1.1, 1e-9);
}

TEST(OperationSettings, ChecksNameWhatIsWrong) {
  const lathectl::control::OperationRating r{5000.0, 0.8, 200.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(check_limit(0.0, r), SettingError::None);  // not set
  EXPECT_EQ(check_limit(5000.0, r), SettingError::None);
  EXPECT_EQ(check_limit(nan, r), SettingError::LimitNotFinite);
  EXPECT_EQ(check_limit(-1.0, r), SettingError::LimitNegative);
  EXPECT_EQ(check_limit(5000.1, r), SettingError::LimitAboveRating);
  EXPECT_EQ(check_feeds(0.0, 0.0, r), SettingError::None);
  EXPECT_EQ(check_feeds(0.1, 0.4, r), SettingError::None);
  EXPECT_EQ(check_feeds(0.4, 0.1, r), SettingError::FeedBounds);
  EXPECT_EQ(check_feeds(0.1, 0.9, r), SettingError::FeedBounds);
  EXPECT_EQ(check_feeds(nan, 0.0, r), SettingError::FeedBounds);
  EXPECT_EQ(check_feeds(-0.1, 0.0, r), SettingError::FeedBounds);
}

TEST(AdaptiveFeedController, SetOperationChangesLimitsOnlyWhenValid) {
  AdaptiveFeedController c;
  AdaptiveFeedController::Params p;
  p.load_limit = 1600.0;
  p.feed_programmed_mm_per_rev = 0.3;
  c.configure(p);
  EXPECT_FALSE(c.set_operation(-1.0, 0.05, 0.6, true));
  EXPECT_FALSE(c.set_operation(1000.0, 0.5, 0.4, true));
  EXPECT_FALSE(c.set_operation(std::numeric_limits<double>::quiet_NaN(), 0.05, 0.6, true));
  EXPECT_EQ(c.params().load_limit, 1600.0);
  ASSERT_TRUE(c.set_operation(1000.0, 0.1, 0.2, false));
  EXPECT_EQ(c.params().load_limit, 1000.0);
  EXPECT_EQ(c.params().feed_programmed_mm_per_rev, 0.2);  // clamped into the new bounds
  EXPECT_EQ(c.params().mode, AdaptiveFeedController::Mode::Fixed);
  ASSERT_TRUE(c.set_operation(1200.0, 0.05, 0.6, true));
  EXPECT_EQ(c.params().mode, p.mode);
  EXPECT_EQ(c.params().feed_programmed_mm_per_rev, 0.3);
  // Regulating at the limit in effect: 1500 N holds the feed at s_min against 1200 N, and lets
  // it rise against 1600 N (the limit set_operation restores).
  AdaptiveFeedController::Output out;
  AdaptiveFeedController::Input in;
  in.rpm = 1000.0;
  in.speed_m_per_min = 150.0;
  in.feed_block = true;
  in.force = 1500.0;
  for (int k = 0; k < 500; ++k) c.update(in, out);
  EXPECT_EQ(out.feed_per_rev_mm, 0.05);
  ASSERT_TRUE(c.set_operation(1600.0, 0.05, 0.6, true));
  for (int k = 0; k < 500; ++k) c.update(in, out);
  EXPECT_GT(out.feed_per_rev_mm, 0.1);
}

// Above the programmed feed: motion's product feed_scale × adaptive-feed (src/emc/motion/
// control.c) against the net override knob × factor, clipped to MAX_FEED_OVERRIDE.
TEST(FeedOverride, SplitsTheNetOverrideIntoCeilingAndFastDecrease) {
  using lathectl::control::split_feed_override;
  // A light cut: the controller wants 3 × the program's; the ceiling is 1.5.
  auto o = split_feed_override(3.0, 1.0, 1.5, 0.001, 1.0, 1.0, true);
  EXPECT_DOUBLE_EQ(o.net, 1.5);
  EXPECT_DOUBLE_EQ(o.scale, 1.5);
  EXPECT_DOUBLE_EQ(o.adaptive, 1.0 / 1.0 * 1.5 / 1.5);  // motion still at 1.0: product 1.0 ≤ net
  // A heavy cut: 0.6 of the program's, with the scale still at 1.5 in motion: adaptive-feed alone.
  o = split_feed_override(0.6, 1.0, 1.5, 0.001, 1.5, 1.5, true);
  EXPECT_DOUBLE_EQ(o.scale, 1.5);  // never lowered in a feed move
  EXPECT_DOUBLE_EQ(o.scale * o.adaptive, 0.6);
  // The operator's knob at 60 %: the net override drops in this call, through adaptive-feed.
  o = split_feed_override(1.5, 0.6, 1.5, 0.001, 1.5, 1.5, true);
  EXPECT_NEAR(o.net, 0.9, 1e-12);
  EXPECT_NEAR(o.scale * o.adaptive, 0.9, 1e-12);
  // Outside feed moves: the knob alone on the scale, adaptive-feed 1 (rapids untouched).
  o = split_feed_override(2.0, 0.8, 1.5, 0.001, 1.5, 1.5, false);
  EXPECT_DOUBLE_EQ(o.scale, 0.8);
  EXPECT_DOUBLE_EQ(o.adaptive, 1.0);
  // A scale lowered outside the move but still 1.5 in motion when the next move starts: the
  // higher one divides, so the product is the net override, not 1.5 × it.
  o = split_feed_override(1.0, 0.8, 1.5, 0.001, 0.8, 1.5, true);
  EXPECT_NEAR(1.5 * o.adaptive, 0.8, 1e-12);
  // Never above the maximum, whatever the knob; rounded up to the resolution.
  o = split_feed_override(1.2345, 2.0, 1.5, 0.001, 1.0, 1.0, true);
  EXPECT_DOUBLE_EQ(o.net, 1.5);
  o = split_feed_override(1.2345, 1.0, 1.5, 0.001, 1.0, 1.0, true);
  EXPECT_NEAR(o.scale, 1.235, 1e-12);
  EXPECT_LE(o.scale * o.adaptive, o.net + 1e-12);
  // MAX_FEED_OVERRIDE 1 (the default): never above the program's feed.
  o = split_feed_override(3.0, 1.0, 1.0, 0.001, 1.0, 1.0, true);
  EXPECT_DOUBLE_EQ(o.scale * o.adaptive, 1.0);
  // Bad inputs stop the feed or fall back to the program's.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  o = split_feed_override(1.0, nan, 1.5, 0.001, 1.0, 1.0, true);
  EXPECT_DOUBLE_EQ(o.scale * o.adaptive, 0.0);
  o = split_feed_override(nan, 1.0, 1.5, 0.001, 1.0, 1.0, true);
  EXPECT_DOUBLE_EQ(o.net, 0.0);
  o = split_feed_override(3.0, 1.0, nan, 0.001, 1.0, 1.0, true);
  EXPECT_DOUBLE_EQ(o.net, 1.0);
}

}  // namespace

// PathBreakage with a late servo period (1 ms thread, limit 550 N): the load of an exit falls from
// 600 N to 0 over 36 ms (from 0.5·limit to the air threshold: 13 ms, outside the 10 ms window)
// while the stock model still predicts the full depth (the worst case: it missed the exit). The
// call after 0.120 s comes late; 12 ms late, it reads 50 N: counted in calls, a 2-call collapse.
namespace {
bool exit_with_late_period(bool measured, double late_s) {
  PathBreakage b;
  b.configure({});  // window 10 ms, air 0.1
  const double limit = 550.0;
  double t = 0.0;
  bool alarm = false;
  auto load = [](double tt) { return std::clamp(600.0 * (1.0 - (tt - 0.1) / 0.036), 0.0, 600.0); };
  double behind = 0.0;
  for (int k = 0; k < 400 && !alarm; ++k) {
    double dt = 0.001;
    if (t < 0.1205 && t + 0.001 >= 0.1205) {
      dt += late_s;
      behind = late_s;
    } else if (behind > 1e-12) {
      dt = 1e-5;
      behind = std::max(behind - 0.001 + 1e-5, 0.0);
    }
    t += dt;
    alarm = b.update(load(t), limit, 2.0, measured ? dt : 0.001);
  }
  return alarm;
}
}  // namespace

TEST(PathBreakage, LatePeriodInAFallingLoadIsNoCollapse) {
  EXPECT_FALSE(exit_with_late_period(true, 0.0));    // on time: 13 ms from 275 N to 55 N
  EXPECT_TRUE(exit_with_late_period(false, 0.012));  // nominal periods: 2 calls, "broken"
  for (double late : {0.001, 0.002, 0.005, 0.008, 0.012, 0.03})
    EXPECT_FALSE(exit_with_late_period(true, late)) << late;
}

// An eccentric blank (e = 1 mm) cut 1.45 mm deep: at least 0.45 − 0.3 (3σ of its random allowance)
// = 0.15 mm is guaranteed, less than half the nominal depth, so the load falling to air once a
// revolution is an interrupted cut. With 2 mm of the 2 mm nominal guaranteed, the same fall is a
// broken tool.
TEST(PathBreakage, AnInterruptedCutIsNoBreakageWhereTheBlankCanGiveNothing) {
  PathBreakage b;
  b.configure({});
  for (int k = 0; k < 20; ++k) EXPECT_FALSE(b.update(1600.0, 2000.0, 1.45, 0.15, 0.0005));
  EXPECT_FALSE(b.update(50.0, 2000.0, 1.45, 0.15, 0.0005));
  PathBreakage sound;
  sound.configure({});
  for (int k = 0; k < 20; ++k) EXPECT_FALSE(sound.update(1600.0, 2000.0, 2.0, 2.0, 0.0005));
  EXPECT_TRUE(sound.update(50.0, 2000.0, 2.0, 2.0, 0.0005));
}

TEST(PathBreakage, ABrokenToolLatchesInThePeriodTheLoadCollapses) {
  PathBreakage b;
  b.configure({});
  for (int k = 0; k < 100; ++k) EXPECT_FALSE(b.update(500.0, 550.0, 2.0, 0.001));
  EXPECT_FALSE(b.update(500.0, 550.0, 2.0, 0.006));  // a late period, still loaded
  EXPECT_FALSE(b.update(500.0, 550.0, 2.0, 1e-5));   // a catch-up call
  EXPECT_TRUE(b.update(10.0, 550.0, 2.0, 0.001));    // broken: the next period
}
