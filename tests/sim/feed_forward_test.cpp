// Feed-forward from the stock model (control::AdaptiveMachine with stock_model): where the
// blank's known geometry raises the depth of cut ahead of the tool, the feed comes down before
// the tool gets there, to what the new depth takes at the limit by the handbook's law times κ,
// the specific force the cut has shown. Here on examples/linuxcnc/step_allowance.toml's bar
// (Ø40 with a Ø44 collar from 15.5 to 30 mm: the depth steps from 2 to 4 mm), cut in a loop
// of the machine and a noiseless copy of the plant it models.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "lathectl/control/types.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "step_allowance_config.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::control {
namespace {

using cutting::LathePlant;
using systems::e_adaptive::RigConfig;

RigConfig config() {
  auto cfg = fixtures::step_allowance_config();
  cfg.disturbances.random_sigma_mm = 0.0;
  return cfg;
}

// The collar seen from the Ø36 pass (x = 18): machine z = −(stock z), the part toward −z.
TEST(FeedForward, DepthAheadSeesTheCollarAndAPlungesWidth) {
  LathePlant p;
  p.configure(config(), {});
  const double r_n = p.nose_radius_mm();
  // Turning toward the chuck from stock z = 5: the bar's 2 mm until the window reaches the
  // collar (its face from 15 to 15.5 mm), then its 4 mm. The programmed point is the tool tip
  // (Q2): the nose's leading point, so the window ends where the path does.
  EXPECT_NEAR(p.depth_ahead_mm(18.0, -5.0, 0.0, -1.0, 9.0), 2.0, 1e-9);
  EXPECT_NEAR(p.depth_ahead_mm(18.0, -5.0, 0.0, -1.0, 15.5 - 5.0 - 0.05), 3.8, 0.05);  // on its face
  EXPECT_NEAR(p.depth_ahead_mm(18.0, -5.0, 0.0, -1.0, 15.5 - 5.0 + 0.05), 4.0, 1e-9);
  // Toward the face, away from the collar: the bar only.
  EXPECT_NEAR(p.depth_ahead_mm(18.0, -5.0, 0.0, 1.0, 10.0), 2.0, 1e-9);
  // A taper going down 1 in 10 over 10 mm ends 1 mm lower: 3 mm below the bar.
  EXPECT_NEAR(p.depth_ahead_mm(18.0, -5.0, -1.0, -10.0, std::hypot(1.0, 10.0) * 0.9), 2.9, 1e-6);
  // Plunging at stock z = 5 from x = 21: the nose's whole width once its end is in the bar
  // (every cell of the circle's chord stands above the edge), nothing while it is above it.
  EXPECT_NEAR(p.depth_ahead_mm(21.0, -5.0, -1.0, 0.0, 2.0), 2.0 * r_n, 0.011);
  EXPECT_EQ(p.depth_ahead_mm(21.0, -5.0, -1.0, 0.0, 0.5), 0.0);
  // No direction, no position: nothing.
  EXPECT_EQ(p.depth_ahead_mm(18.0, -5.0, 0.0, 0.0, 5.0), 0.0);
  EXPECT_EQ(p.depth_ahead_mm(std::nan(""), -5.0, 0.0, -1.0, 5.0), 0.0);
}

struct Pass {
  double peak_rev = 0.0;      // largest per-revolution mean of the true Pz [N]
  double first_ceiling_z = 0.0;  // stock z of the tool when the collar's ceiling came
  double ceiling = 0.0;       // that ceiling [mm/rev]
  double kappa = 0.0;         // κ then
  double speed = 0.0;         // the cutting speed the machine was given then [m/min]
  double time_s = 0.0;        // to the end of the pass
  double hardness = 0.0;      // ĥ at the end of the pass
  bool stock_ahead = false;   // the reason was given
  bool alarm = false;
};

// One pass at x = 18 from machine z = +2 (air) to −26 (in the collar), prior-art control at a
// constant 1200 rpm (150 m/min at Ø40), the tool fed at the machine's feed per revolution.
Pass cut(bool feed_forward, double hardness = 1.0) {
  RigConfig cfg = config();
  if (hardness != 1.0) cfg.disturbances.hardness = {{0.0, hardness}, {60.0, hardness}};
  LathePlant truth;
  truth.configure(cfg, {});
  AdaptiveMachine::Params mp;
  mp.controller = cfg.controller;
  mp.controller.mode = AdaptiveFeedController::Mode::ForceFeed;
  mp.controller.feed_programmed_mm_per_rev = 0.6;  // the regulator, not the F word, decides
  mp.rating.limit_max = 1e300;
  mp.rating.feed_max_mm_per_rev = 1e300;
  mp.stock_model = true;
  mp.feed_forward = feed_forward;
  mp.life_law = true;  // (its speed factor acts only in seed 004's mode; ĥ is reported)
  mp.process = config();  // the blank as the machine knows it: nominal hardness
  AdaptiveMachine m;
  m.configure(mp);
  const double dt = 0.001, rpm = 1200.0;
  PerRevolutionMean rev(dt, 100.0);
  AdaptiveMachine::Output out;
  Pass r;
  double x = 18.0, z = 2.0;
  LathePlant::Output po;
  for (int k = 0; z > -26.0 && k < 200000; ++k) {
    truth.step({x, z, rpm}, dt, po);
    AdaptiveMachine::Input in;
    in.nominal_period_s = dt;
    in.force = po.force_measured;
    in.rpm = rpm;
    in.rpm_programmed = rpm;
    in.requested_vel = 0.6;
    in.motion_type = static_cast<std::int32_t>(AdaptiveMachine::Motion::Feed);
    in.x_mm = x;
    in.z_mm = z;
    in.cutting_speed_m_per_min = po.speed_m_per_min;
    in.tool_number = 1;
    in.program_line = 1;
    m.update(in, out);
    // (the first ceiling past the bar's face: the entry from air into the bar has its own)
    if (out.feed_ceiling_mm_per_rev > 0.0 && r.first_ceiling_z == 0.0 && -z > 5.0)
      r.first_ceiling_z = -z;
    // the ceiling once the look-ahead sees the collar's full 4 mm
    if (out.feed_ceiling_mm_per_rev > 0.0 && r.ceiling == 0.0 && out.depth_ahead_mm > 3.999) {
      r.ceiling = out.feed_ceiling_mm_per_rev;
      r.kappa = out.specific_force_ratio;
      r.speed = in.cutting_speed_m_per_min;
    }
    r.stock_ahead = r.stock_ahead || out.reason == Reason::StockAhead;
    r.alarm = r.alarm || out.alarm;
    if (po.in_contact) r.peak_rev = std::max(r.peak_rev, rev.push(po.Pz_N, rpm));
    z -= 0.6 * out.feed_factor * rpm / 60.0 * dt;  // the F word times the machine's factor
    r.time_s += dt;
  }
  r.hardness = out.hardness_estimate;
  return r;
}

TEST(FeedForward, TheFeedComesDownBeforeTheCollarAndHoldsTheLimitThrough) {
  const RigConfig cfg = config();
  const double limit = cfg.controller.load_limit;
  const Pass with = cut(true);
  const Pass without = cut(false);
  EXPECT_FALSE(with.alarm);
  EXPECT_FALSE(without.alarm);
  // Down before the nose meets the collar's face (stock z 15 − r_n), within the look-ahead
  // (the nose and 1.5 revolutions at the highest feed, 0.6 mm/rev: 0.9 mm).
  const double r_n = cfg.cutting.nose_radius_mm;
  EXPECT_TRUE(with.stock_ahead);
  EXPECT_LT(with.first_ceiling_z, 15.0 - r_n);
  EXPECT_GT(with.first_ceiling_z, 15.0 - r_n - 0.9 - 0.1);
  // κ from the 2 mm cut: the plant is the handbook's law on a sharp tool, so κ ≈ 1 (the wear
  // the plant adds over a few seconds in the cut is a few per cent), and the ceiling is the feed
  // at which the handbook's Pz at 4 mm is the limit over κ (at the speed the machine was given:
  // the surface it cuts now, Ø40 at 1200 rpm).
  EXPECT_NEAR(with.kappa, 1.0, 0.05);
  cutting::CuttingModel law;
  law.configure(cfg.cutting);
  EXPECT_NEAR(with.speed, std::numbers::pi * 40.0 * 1200.0 / 1000.0, 0.5);
  EXPECT_NEAR(with.kappa * law.forces({4.0, with.ceiling, with.speed, 1.0, 1.0}).Pz, limit,
              1e-3 * limit);
  // Through the collar: the per-revolution force within 5 % of the limit with the feed-forward;
  // without it the regulator answers a revolution late.
  EXPECT_LT(with.peak_rev, 1.05 * limit);
  EXPECT_GT(without.peak_rev, with.peak_rev + 0.05 * limit);
  std::printf("collar 2 → 4 mm at 1600 N: per-rev peak %.0f N with feed-forward (ceiling %.3f "
              "mm/rev at stock z %.2f, κ %.3f), %.0f N without; pass %.2f s against %.2f s\n",
              with.peak_rev, with.ceiling, with.first_ceiling_z, with.kappa, without.peak_rev,
              with.time_s, without.time_s);
}

// The tool-life law's hardness: a bar 1.25× as hard as the material's nominal (K_mp = h^kmp in
// the plant) shows κ = 1.25^kmp (times the plant's wear over a few seconds, a few per cent), and
// ĥ = κ^(1/kmp) recovers it; the feed-forward's ceiling, κ times the law, then holds the collar
// too.
TEST(FeedForward, TheSpecificForceShowsTheHardness) {
  const RigConfig cfg = config();
  const double kmp = cfg.cutting.material.kmp_exponent;
  ASSERT_GT(kmp, 0.0);
  const Pass nominal = cut(true);
  const Pass hard = cut(true, 1.25);
  EXPECT_NEAR(nominal.hardness, 1.0, 0.03);
  EXPECT_NEAR(hard.hardness, 1.25, 0.04);
  EXPECT_NEAR(hard.kappa / nominal.kappa, std::pow(1.25, kmp), 0.02);
  EXPECT_LT(hard.peak_rev, 1.05 * cfg.controller.load_limit);
  EXPECT_FALSE(hard.alarm);
  std::printf("hardness 1.25: κ %.3f (nominal bar %.3f), ĥ %.3f (nominal %.3f); collar peak %.0f N\n",
              hard.kappa, nominal.kappa, hard.hardness, nominal.hardness, hard.peak_rev);
}

}  // namespace
}  // namespace lathectl::control
