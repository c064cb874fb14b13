// System B's surface figure (metrics.hpp, Surface) against the closed forms of the feed marks a
// nose radius r leaves: Rz = p²/(8r) for a mark spacing p, Ra ≈ p²/(32r) (Shaw, "Metal Cutting
// Principles", the geometric roughness of a round-nosed tool). Checked on short cuts of
// b_twin_feed_division's shaft: one tool at a constant feed (p = s), one tool under a programmed
// staircase (each level S_k = S_min + k·ΔS holds for the same path Δl, so the path-mean Rz is the
// mean of (S_k/n)²/(8r) over the cycle's 2n_s segments), and twin turrets in feed division
// running together (marks of both tools, half a revolution apart: p = s/2).

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/b_chatter/metrics.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl {
namespace {

using systems::b_chatter::RigConfig;
using BRun = systems::b_chatter::Run;

RigConfig shaft(systems::b_chatter::TwinSetup setup, double feed_mm_per_rev, double length_mm) {
  const auto sc = systems::parse_scenario(test::example_text("b_twin_feed_division"), "mem.toml",
                                          test::library());
  RigConfig b = sc.get<systems::b_chatter::Settings>().rig;
  b.setup = setup;
  b.feed_mm_per_rev = feed_mm_per_rev;
  b.z_end_mm = b.z_start_mm + length_mm;
  b.source = control::ModulationSource::None;
  b.tool2_lag_mm = 0.0;
  return b;
}

std::unique_ptr<BRun> measured(const RigConfig& b) {
  auto r = std::make_unique<BRun>();
  r->rig.configure(b, 2e-5, 1e-3, 60.0);
  r->rig.run();
  r->measure = std::make_unique<systems::b_chatter::Measure>(
      r->rig, b.setup != systems::b_chatter::TwinSetup::Single, nullptr);
  r->rig.recorder().replay(*r->measure);
  r->measure->result(*r, 5.0);
  return r;
}

TEST(SystemBSurface, OneToolAtAConstantFeed) {
  const RigConfig b = shaft(systems::b_chatter::TwinSetup::Single, 0.05, 2.0);
  const auto run = measured(b);
  const BRun& r = *run;
  const double rn = b.cutting.nose_radius_mm;
  const double rz = 0.05 * 0.05 / (8.0 * rn) * 1e3;  // µm
  EXPECT_NEAR(r.surface.Rz_programmed_um, rz, 1e-12);
  EXPECT_NEAR(r.surface.Ra_programmed_um, rz / 4.0, 1e-12);
  // The spindle droops a little under the cut's torque (the feed rate holds): p = S/n a shade
  // above s; the feed drive's first 10 ms reach the part before it has settled.
  EXPECT_NEAR(r.surface.Rz_mean_um / rz, 1.0, 0.01);
  EXPECT_NEAR(r.surface.Ra_mean_um / (rz / 4.0), 1.0, 0.01);
  EXPECT_NEAR(r.surface.length_mm, 2.0, 0.05);
}

TEST(SystemBSurface, ProgrammedStaircaseIsTheMeanOverItsLevels) {
  RigConfig b = shaft(systems::b_chatter::TwinSetup::Single, 0.05, 2.0);
  // Cycle 2·n_s·Δl = 1 mm: the 1 mm approach and the 2 mm measured are whole cycles.
  b.source = control::ModulationSource::Programmed;
  b.programmed = {20.0, 10.0, 0.125, 4};
  const auto run = measured(b);
  const BRun& r = *run;
  const double rn = b.cutting.nose_radius_mm, n = b.rpm;
  double sum = 0.0;
  for (int j = 0; j < 8; ++j) {
    const int k = j <= 4 ? j : 8 - j;
    const double p = (20.0 + 10.0 * k) / n;  // mm per revolution
    sum += p * p / (8.0 * rn) * 1e3;
  }
  const double rz_mean = sum / 8.0;
  // The feed drive (30 Hz) rounds each step over ≈ 5 ms, a few % of a 0.125 mm segment.
  EXPECT_NEAR(r.surface.Rz_mean_um / rz_mean, 1.0, 0.03);
  EXPECT_NEAR(r.surface.Rz_max_um / (60.0 * 60.0 / (n * n) / (8.0 * rn) * 1e3), 1.0, 0.01);
  EXPECT_NEAR(r.surface.Rz_min_um / (20.0 * 20.0 / (n * n) / (8.0 * rn) * 1e3), 1.0, 0.02);
}

TEST(SystemBSurface, FeedDivisionTogetherHalvesTheMarks) {
  const RigConfig b = shaft(systems::b_chatter::TwinSetup::FeedDivision, 0.06, 2.0);
  const auto run = measured(b);
  const BRun& r = *run;
  const double rn = b.cutting.nose_radius_mm;
  const double rz = 0.03 * 0.03 / (8.0 * rn) * 1e3;
  EXPECT_NEAR(r.surface.Rz_programmed_um, rz, 1e-12);
  EXPECT_NEAR(r.surface.Rz_mean_um / rz, 1.0, 0.02);
}

}  // namespace
}  // namespace lathectl
