// The CNC module of seed 001: the staircase executes (S_min, ΔS, Δl, n_s) exactly; the plan obeys
// the seed's constraints (ΔS a multiple of 0.1 mm/min, Δl of the resolution), the quenching
// condition A_P ≥ c·a0·m_d·|ω_d² − ω_m²| and the programmed time-mean feed; the controller
// engages and releases with reason codes, honours the block's turret flag and the programmed
// variant.
#include "lathectl/control/modulated_feed.hpp"

#include <gtest/gtest.h>

#include <vector>


#include <algorithm>

#include <cmath>
#include <numbers>

namespace lathectl::control {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

TEST(ModulatedFeedGenerator, WalksTheStaircaseUpAndDownByPath) {
  const ModulationPlan plan{100.0, 10.0, 0.5, 4};
  ModulatedFeedGenerator g;
  g.start(plan);
  EXPECT_DOUBLE_EQ(plan.s_max_mm_per_min(), 140.0);
  EXPECT_DOUBLE_EQ(plan.cycle_length_mm(), 4.0);
  const double expected[] = {100, 110, 120, 130, 140, 130, 120, 110, 100, 110};
  // Small path steps; sample the middle of each Δl segment.
  double path = 0.0, time_min = 0.0, path_sum = 0.0;
  for (int seg = 0; seg < 10; ++seg) {
    double f = 0.0;
    for (int k = 0; k < 50; ++k) {
      f = g.advance(0.01);
      path += 0.01;
      if (seg < 8) {
        time_min += 0.01 / f;
        path_sum += 0.01;
      }
      if (k == 25) {
        EXPECT_DOUBLE_EQ(f, expected[seg]) << seg;
      }
    }
  }
  // Time-mean feed over one cycle = harmonic mean of the levels.
  EXPECT_NEAR(path_sum / time_min, plan.time_mean_feed(), 1e-3 * plan.time_mean_feed());
  EXPECT_LT(plan.time_mean_feed(), 120.0);  // below the path mean
}

TEST(ModulatedFeedGenerator, OffsetSwingMatchesIntegration) {
  const ModulationPlan plan{60.0, 20.0, 0.2, 5};
  const double other = plan.time_mean_feed();
  ModulatedFeedGenerator g;
  g.start(plan);
  // Integrate δ = ∫(S − S_other) dt along two cycles in small path steps.
  double delta = 0.0, lo = 0.0, hi = 0.0;
  for (int k = 0; k < 4000; ++k) {
    const double f = g.feed();
    const double dp = 0.0005;
    delta += dp - other * (dp / f);
    lo = std::min(lo, delta);
    hi = std::max(hi, delta);
    (void)g.advance(dp);
  }
  EXPECT_NEAR(hi - lo, plan.offset_swing_mm(other), 2e-3 * plan.offset_swing_mm(other));
}

ModulatedFeedController::Params params() {
  ModulatedFeedController::Params p;
  p.part_mass_kg = 3.0;
  p.radial_force_ratio = 0.3;
  p.force_feed_exponent = 0.51;
  return p;
}

TEST(ModulatedFeedController, PlanMeetsTheQuenchingConditionAndTheSeedsQuanta) {
  ModulatedFeedController m;
  m.configure(params());
  double wm = 0, req = 0, got = 0;
  bool limited = true;
  const double wd = kTwoPi * 230.0;
  // Small a0: the condition can be met inside the limits.
  const ModulationPlan plan =
      m.plan_for(0.05e-6, wd, 1000.0, 100.0, 100.0, 800.0, wm, req, got, limited);
  EXPECT_FALSE(limited);
  EXPECT_NEAR(req, 1.41 * 0.05e-6 * 3.0 * std::abs(wd * wd - wm * wm), 1e-9);
  EXPECT_GE(got, req * (1.0 - 1e-3));
  // A_P from the force: F = 0.3·1000 W/(100/60 m/s) = 180 N, F ∝ S^0.51.
  const double f = 180.0;
  EXPECT_NEAR(got,
              0.5 * f *
                  (std::pow(plan.s_max_mm_per_min() / 100.0, 0.51) -
                   std::pow(plan.s_min_mm_per_min / 100.0, 0.51)),
              1e-9);
  EXPECT_NEAR(std::remainder(plan.ds_mm_per_min, 0.1), 0.0, 1e-9);
  EXPECT_NEAR(std::remainder(plan.s_min_mm_per_min, 0.1), 0.0, 1e-9);
  EXPECT_NEAR(std::remainder(plan.dl_mm, 0.001), 0.0, 1e-12);
  EXPECT_EQ(plan.n_s, 5);
  EXPECT_NEAR(plan.time_mean_feed(), 100.0, 0.5);  // the programmed feed kept (S_min in 0.1s)
  // ω_m from the path: 2 Hz wanted, Δl rounded to 1 µm.
  EXPECT_NEAR(wm / kTwoPi, 2.0, 0.02);
  EXPECT_NEAR(wm, kTwoPi * (100.0 / 60.0) / plan.cycle_length_mm(), 1e-12);
}

TEST(ModulatedFeedController, LargeVibrationIsLimitedBySpan) {
  ModulatedFeedController m;
  m.configure(params());
  double wm = 0, req = 0, got = 0;
  bool limited = false;
  const ModulationPlan plan =
      m.plan_for(200e-6, kTwoPi * 230.0, 1000.0, 100.0, 100.0, 800.0, wm, req, got, limited);
  EXPECT_TRUE(limited);
  EXPECT_LT(got, req);
  EXPECT_GE(plan.s_min_mm_per_min, 0.2 * 100.0 - 0.05);
  EXPECT_LE(plan.s_max_mm_per_min(), 2.0 * 100.0 + 0.5);
}

TEST(ModulatedFeedController, StaysOutOfEntrainmentBands) {
  auto p = params();
  p.drive_bandwidth_Hz = 1000.0;
  const double fd = 30.0;
  for (double wanted : {fd / 3.0, fd / 2.0, fd, 2.0 * fd}) {
    p.modulation_frequency_Hz = wanted;
    ModulatedFeedController m;
    m.configure(p);
    double wm = 0, req = 0, got = 0;
    bool limited = false;
    (void)m.plan_for(1e-6, kTwoPi * fd, 1000.0, 100.0, 3000.0, 800.0, wm, req, got, limited);
    for (double r : {1.0 / 3.0, 0.5, 1.0, 2.0, 3.0})
      EXPECT_FALSE(wm / kTwoPi > 0.85 * r * fd && wm / kTwoPi < 1.15 * r * fd)
          << wanted << " " << r;
  }
}

TEST(ModulatedFeedController, DesynchronisingLengthensTheRampUntilTheOffsetSwingsAChip) {
  auto p = params();
  p.modulation_frequency_Hz = 8.0;
  p.drive_bandwidth_Hz = 100.0;
  p.desync_fraction = 1.0;
  ModulatedFeedController m;
  m.configure(p);
  double wm = 0, req = 0, got = 0;
  bool limited = false;
  const ModulationPlan plan =
      m.plan_for(100e-6, kTwoPi * 230.0, 1000.0, 100.0, 100.0, 800.0, wm, req, got, limited);
  EXPECT_GE(plan.offset_swing_mm(100.0), 100.0 / 800.0 * (1.0 - 1e-9));
  EXPECT_LT(wm / kTwoPi, 8.0);
}

ModulatedFeedController::Input cutting_input(double a0) {
  ModulatedFeedController::Input in;
  in.a0_m = a0;
  in.omega_d_rad_per_s = a0 > 0.0 ? kTwoPi * 230.0 : 0.0;
  in.cut_power_W = 1000.0;
  in.speed_m_per_min = 100.0;
  in.rpm = 800.0;
  in.feed_programmed_mm_per_min[0] = 100.0;
  in.feed_programmed_mm_per_min[1] = 100.0;
  in.feed_block = true;
  return in;
}

TEST(ModulatedFeedController, EngagesAboveTheDeadZoneOnTheFlaggedTurretOnly) {
  ModulatedFeedController m;
  m.configure(params());
  ModulatedFeedController::Output out;
  auto in = cutting_input(0.0);
  in.turret = Turret::Left;
  for (int k = 0; k < 100; ++k) {
    m.update(in, out);
    EXPECT_EQ(out.reason, Reason::None);
    EXPECT_FALSE(out.engaged);
    EXPECT_DOUBLE_EQ(out.feed_mm_per_min[1], 100.0);
  }
  in = cutting_input(20e-6);
  in.turret = Turret::Left;
  bool engaged_reason = false;
  double lo = 1e9, hi = 0.0;
  for (int k = 0; k < 5000; ++k) {
    in.path_mm[0] += 100.0 / 60.0 * 1e-3;
    in.path_mm[1] += 100.0 / 60.0 * 1e-3;
    m.update(in, out);
    engaged_reason |= out.reason == Reason::ModulationEngaged;
    if (out.engaged) {
      lo = std::min(lo, out.feed_mm_per_min[1]);
      hi = std::max(hi, out.feed_mm_per_min[1]);
      EXPECT_DOUBLE_EQ(out.feed_mm_per_min[0], 100.0);  // the other turret keeps its feed
    }
  }
  EXPECT_TRUE(engaged_reason);
  EXPECT_TRUE(out.engaged);
  EXPECT_EQ(out.reason, Reason::ModulationLimited);  // 20 µm needs far more than feed can give
  EXPECT_NEAR(lo, out.plan.s_min_mm_per_min, 1e-9);
  EXPECT_NEAR(hi, out.plan.s_max_mm_per_min(), 1e-9);
  // The block ends: released, programmed feeds.
  in.feed_block = false;
  m.update(in, out);
  EXPECT_EQ(out.reason, Reason::ModulationReleased);
  EXPECT_FALSE(out.engaged);
}

TEST(ModulatedFeedController, SeedsLiteralReleaseBelowTheDeadZone) {
  auto p = params();
  p.release_below_dead_zone = true;
  p.release_time_s = 0.01;
  ModulatedFeedController m;
  m.configure(p);
  ModulatedFeedController::Output out;
  auto in = cutting_input(2e-6);
  for (int k = 0; k < 100; ++k) m.update(in, out);
  ASSERT_TRUE(out.engaged);
  in = cutting_input(0.0);
  bool released = false;
  for (int k = 0; k < 20; ++k) {
    m.update(in, out);
    released |= out.reason == Reason::ModulationReleased;
  }
  EXPECT_TRUE(released);
  EXPECT_FALSE(out.engaged);
  EXPECT_DOUBLE_EQ(out.feed_mm_per_min[0], 100.0);
}

TEST(ModulatedFeedController, ProgrammedVariantRunsTheBlocksParameters) {
  ModulatedFeedController m;
  m.configure(params());
  ModulatedFeedController::Output out;
  auto in = cutting_input(0.0);
  in.source = ModulationSource::Programmed;
  in.programmed = {50.0, 20.0, 0.1, 3};
  double hi = 0.0;
  for (int k = 0; k < 3000; ++k) {
    in.path_mm[0] += 0.001;
    m.update(in, out);
    hi = std::max(hi, out.feed_mm_per_min[0]);
    EXPECT_EQ(out.reason, Reason::ModulationProgrammed);
  }
  EXPECT_DOUBLE_EQ(hi, 110.0);
  EXPECT_DOUBLE_EQ(out.plan.ds_mm_per_min, 20.0);
}

TEST(ModulatedFeedController, NoPowerNoPlan) {
  ModulatedFeedController m;
  m.configure(params());
  ModulatedFeedController::Output out;
  auto in = cutting_input(10e-6);
  in.cut_power_W = 0.0;
  for (int k = 0; k < 100; ++k) m.update(in, out);
  EXPECT_EQ(out.reason, Reason::ModulationNoForce);
  EXPECT_FALSE(out.engaged);
  EXPECT_DOUBLE_EQ(out.feed_mm_per_min[0], 100.0);
}

TEST(ModulatedFeedController, UnconfiguredAndBadParameters) {
  ModulatedFeedController m;
  ModulatedFeedController::Output out;
  m.update(cutting_input(1e-6), out);  // before configure(): nothing formed, nothing said
  EXPECT_FALSE(out.engaged);
  EXPECT_EQ(out.reason, Reason::None);
  EXPECT_EQ(out.feed_mm_per_min[0], 0.0);
  auto p = params();
  p.n_s = 0;
  EXPECT_THROW(m.configure(p), std::invalid_argument);
  p = params();
  p.s_min_fraction = 1.2;
  EXPECT_THROW(m.configure(p), std::invalid_argument);
  p = params();
  p.coefficient = 0.0;
  EXPECT_THROW(m.configure(p), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::control

namespace lathectl::control {
namespace {
TEST(ModulatedFeedGenerator, RetuningKeepsThePhase) {
  ModulatedFeedGenerator g;
  g.start({100.0, 10.0, 0.5, 4});
  (void)g.advance(2.6);  // segment 5 (levels 0..4 up, then 3), 0.1 mm into it
  ASSERT_EQ(g.segment(), 5);
  g.retune({80.0, 20.0, 1.0, 4});
  EXPECT_EQ(g.segment(), 5);
  EXPECT_DOUBLE_EQ(g.feed(), 80.0 + 3 * 20.0);
  (void)g.advance(0.79);  // 0.2 + 0.79 < 1.0: still in segment 5
  EXPECT_EQ(g.segment(), 5);
  (void)g.advance(0.02);
  EXPECT_EQ(g.segment(), 6);
}
// Re-plan cost bounded in n_s (issue "Results a user can trust", finding 4). Above 32 increments
// the staircase sums are taken in closed form (digamma): check them against term-by-term sums,
// then the re-plan's time at the largest n_s the scenarios accept.
double brute_time_mean(const ModulationPlan& p) {
  double inv = 0.0;
  for (int j = 0; j < 2 * p.n_s; ++j) {
    const int k = j <= p.n_s ? j : 2 * p.n_s - j;
    inv += 1.0 / (p.s_min_mm_per_min + k * p.ds_mm_per_min);
  }
  return 2.0 * p.n_s / inv;
}
double brute_swing(const ModulationPlan& p, double s_other) {
  double c = 0.0, lo = 0.0, hi = 0.0;
  for (int j = 0; j < 2 * p.n_s; ++j) {
    const int k = j <= p.n_s ? j : 2 * p.n_s - j;
    c += p.dl_mm * (1.0 - s_other / (p.s_min_mm_per_min + k * p.ds_mm_per_min));
    lo = std::min(lo, c);
    hi = std::max(hi, c);
  }
  return hi - lo;
}

TEST(ModulationPlan, ClosedFormSumsMatchTermByTerm) {
  for (int n : {33, 50, 200, 1000}) {
    for (double s_min : {0.1, 3.0, 80.0, 240.0}) {
      for (double ds : {0.1, 1.3, 20.0}) {
        const ModulationPlan p{s_min, ds, 0.01, n};
        const double want = brute_time_mean(p);
        EXPECT_NEAR(p.time_mean_feed(), want, 1e-12 * want) << n << " " << s_min << " " << ds;
        for (double s_other : {0.5 * s_min, want, s_min + 0.5 * n * ds, s_min + 2.0 * n * ds}) {
          const double sw = brute_swing(p, s_other);
          EXPECT_NEAR(p.offset_swing_mm(s_other), sw, 1e-10 * std::max(sw, 1e-3))
              << n << " " << s_min << " " << ds << " " << s_other;
        }
      }
    }
  }
}

TEST(ModulatedFeedController, ReplanAtLargestNsKeepsTheMean) {
  for (int n : {5, 50, 1000}) {
    ModulatedFeedController m;
    ModulatedFeedController::Params p;
    p.n_s = n;
    m.configure(p);
    double wm = 0, req = 0, got = 0;
    bool lim = false;
    const auto plan =
        m.plan_for(2e-5, 2.0 * std::numbers::pi * 230.0, 1000.0, 100.0, 246.0, 820.0, wm, req, got, lim);
    ASSERT_TRUE(plan.active()) << n;
    // Mean kept to the quanta (S_min rounded to 0.1 mm/min moves the mean by ≤ 0.05).
    EXPECT_NEAR(plan.time_mean_feed(), 246.0, 0.06) << n;
    // Its cost over n_s is measured in bench/ (BM_ModulatedFeedController_Plan), not timed here.
  }
}

}  // namespace
}  // namespace lathectl::control

namespace lathectl::control {
namespace {
// The re-plan through a ModulationPlanner (the HAL component's slower thread): update() posts the
// request, run() plans it, the next update() takes exactly the plan update() would have made
// itself; before the planner has run once, update() plans itself; a request from an ended block
// is dropped.
TEST(ModulationPlanner, HandsOverThePlanInlinePlanningWouldMake) {
  auto p = params();
  p.engage_time_s = 0.0;
  ModulatedFeedController inline_m, deferred;
  inline_m.configure(p);
  deferred.configure(p);
  ModulationPlanner planner;
  deferred.use_planner(&planner);
  auto in = cutting_input(5e-6);
  ModulatedFeedController::Output a, b;
  (void)inline_m.update(in, a);
  (void)deferred.update(in, b);
  ASSERT_TRUE(a.engaged);
  EXPECT_TRUE(b.engaged);  // no planner thread yet: planned inside update()
  EXPECT_EQ(deferred.plan_counts().made_inline, 1U);
  EXPECT_EQ(deferred.plan_counts().taken, 0U);
  // Now with the planner alive: a new block, a request, the plan one planner run later.
  ModulatedFeedController d2;
  d2.configure(p);
  d2.use_planner(&planner);
  EXPECT_FALSE(planner.run(d2));  // alive, nothing asked yet
  (void)d2.update(in, b);
  EXPECT_FALSE(b.engaged);  // asked, not answered
  (void)d2.update(in, b);
  EXPECT_FALSE(b.engaged);  // still not: no second request while one is out
  EXPECT_TRUE(planner.run(d2));
  EXPECT_FALSE(planner.run(d2));  // nothing new
  (void)d2.update(in, b);
  ASSERT_TRUE(b.engaged);
  EXPECT_EQ(b.reason, Reason::ModulationEngaged);
  EXPECT_EQ(d2.plan_counts().made_inline, 0U);  // the servo side planned nothing itself
  EXPECT_EQ(d2.plan_counts().taken, 1U);
  EXPECT_EQ(b.plan.n_s, a.plan.n_s);
  EXPECT_EQ(b.plan.s_min_mm_per_min, a.plan.s_min_mm_per_min);
  EXPECT_EQ(b.plan.ds_mm_per_min, a.plan.ds_mm_per_min);
  EXPECT_EQ(b.plan.dl_mm, a.plan.dl_mm);
  EXPECT_EQ(b.force_amplitude_required_N, a.force_amplitude_required_N);
  // A request whose block ends before the answer comes is not applied to the next block.
  ModulatedFeedController d3;
  d3.configure(p);
  d3.use_planner(&planner);
  (void)d3.update(in, b);  // posts
  in.feed_block = false;
  (void)d3.update(in, b);  // the block ends
  EXPECT_TRUE(planner.run(d3));  // answers the old request
  in.feed_block = true;
  in.a0_m = 10e-6;
  (void)d3.update(in, b);  // the new block asks anew
  (void)d3.update(in, b);  // the old answer arrives: dropped
  EXPECT_FALSE(b.engaged);
  EXPECT_TRUE(planner.run(d3));
  (void)d3.update(in, b);
  ASSERT_TRUE(b.engaged);
  ModulatedFeedController::Output c;
  ModulatedFeedController ref;
  ref.configure(p);
  (void)ref.update(in, c);
  EXPECT_EQ(b.plan.ds_mm_per_min, c.plan.ds_mm_per_min);  // the plan for 10 µm, not 5 µm
  EXPECT_EQ(b.force_amplitude_required_N, c.force_amplitude_required_N);
}
}  // namespace
}  // namespace lathectl::control
