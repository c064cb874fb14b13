// The path-driven lathe plant (the LinuxCNC plant component's model) against closed forms:
// steady longitudinal turning removes t·s per revolution and gives the handbook force at the
// uncut diameter; facing swaps the roles (s radial, t axial); the first revolution builds the
// chip up; the workpiece keeps what earlier passes cut (with their feed marks); bad stock is
// refused.

#include "lathectl/cutting/lathe_plant.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "step_allowance_config.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::sim {
using cutting::LathePlant;
using systems::e_adaptive::RigConfig;
namespace {

RigConfig config() { return fixtures::step_allowance_config(); }

// Moves the tool from (x0, z0) to (x1, z1) at `feed` mm/rev, 1 ms steps; returns the last output.
LathePlant::Output move(LathePlant& p, double x0, double z0, double x1, double z1, double rpm,
                        double feed) {
  const double len = std::hypot(x1 - x0, z1 - z0);
  const double dt = 1e-3;
  const auto n = static_cast<int>(len / (feed * rpm / 60.0) / dt);
  LathePlant::Output out;
  for (int k = 1; k <= n; ++k) {
    const double f = static_cast<double>(k) / n;
    p.step({x0 + f * (x1 - x0), z0 + f * (z1 - z0), rpm}, dt, out);
  }
  return out;
}

// Mean outputs over the last revolution of a move (a sample depends on where the window's ends
// fall between the grid's cells; the mean does not).
struct RevMean {
  double depth = 0, feed = 0, speed = 0, pz = 0, power = 0;
};
RevMean move_mean(LathePlant& p, double x, double z0, double z1, double rpm, double feed) {
  const double dt = 1e-3;
  const double v = feed * rpm / 60.0;
  const auto n = static_cast<int>(std::abs(z1 - z0) / v / dt);
  const auto rev = static_cast<int>(60.0 / rpm / dt);
  RevMean m;
  LathePlant::Output out;
  for (int k = 1; k <= n; ++k) {
    p.step({x, z0 + (z1 - z0) * k / n, rpm}, dt, out);
    if (k > n - rev) {
      m.depth += out.depth_mm / rev;
      m.feed += out.feed_per_rev_mm / rev;
      m.speed += out.speed_m_per_min / rev;
      m.pz += out.Pz_N / rev;
      m.power += out.cut_power_W / rev;
    }
  }
  return m;
}

double handbook_pz(const RigConfig& c, double t, double s, double v) {
  cutting::CuttingModel m;
  m.configure(c.cutting);
  return m.forces({t, s, v, 1.0, 1.0}).Pz;
}

TEST(LathePlant, SteadyTurningGivesTheHandbookForceAtTheUncutDiameter) {
  const auto c = config();
  LathePlant p;
  p.configure(c, {});
  // 40 mm bar to 36 mm (t = 2) at 0.25 mm/rev, 800 rpm, from z = +2 to z = -12.
  const auto m = move_mean(p, 18.0, 2.0, -12.0, 800.0, 0.25);
  EXPECT_NEAR(m.depth, 2.0, 1e-3);
  EXPECT_NEAR(m.feed, 0.25, 1e-4);
  const double v = std::numbers::pi * 40.0 * 800.0 / 1000.0;
  EXPECT_NEAR(m.speed, v, 0.01);
  EXPECT_NEAR(m.pz, handbook_pz(c, 2.0, 0.25, v), 2e-3 * m.pz);
  EXPECT_NEAR(m.power, m.pz * v / 60.0, 2e-3 * m.power);
  EXPECT_NEAR(p.radius_mm(10.0), 18.0, 1e-9);  // cut to the tool's radius
  EXPECT_NEAR(p.radius_mm(20.0), 22.0, 1e-9);  // the collar, not reached yet
}

// The chip window is one revolution whatever the step: at 3000 rpm a 1 ms step is 18° of the
// spindle, and the feed per revolution must still be the path travelled in one turn.
// Not homed (no position): nothing is cut and every output is a number — the LinuxCNC plant's
// drive-power pin is built from the cutting power, and a NaN there alarmed the power sensor.
TEST(LathePlant, NoPositionCutsNothingAndGivesNumbers) {
  LathePlant p;
  p.configure(config(), {});
  LathePlant::Output out;
  for (int k = 0; k < 100; ++k) p.step({std::nan(""), std::nan(""), 800.0}, 1e-3, out);
  EXPECT_EQ(out.cut_power_W, 0.0);
  EXPECT_EQ(out.speed_m_per_min, 0.0);
  EXPECT_FALSE(out.in_contact);
  EXPECT_TRUE(std::isfinite(out.force_measured));
}

TEST(LathePlant, FeedPerRevolutionIsExactAtHighSpeed) {
  const auto c = config();
  for (double rpm : {300.0, 1222.0, 3000.0}) {
    LathePlant p;
    p.configure(c, {});
    const auto m = move_mean(p, 18.0, 2.0, -12.0, rpm, 0.3);
    EXPECT_NEAR(m.feed, 0.3, 3e-4) << rpm;
    EXPECT_NEAR(m.depth, 2.0, 2e-3) << rpm;
  }
}

TEST(LathePlant, FirstRevolutionBuildsTheChipUp) {
  const auto c = config();
  LathePlant p;
  p.configure(c, {});
  // Half a revolution after the nose meets the face: about half the chip.
  (void)move(p, 18.0, 2.0, 18.0, 0.8, 600.0, 0.3);  // nose (r 0.8) touches the face at z = 0.8
  const auto half = move(p, 18.0, 0.8, 18.0, 0.8 - 0.15, 600.0, 0.3);
  const auto full = move(p, 18.0, 0.65, 18.0, -3.0, 600.0, 0.3);
  EXPECT_LT(half.Pz_N, 0.7 * full.Pz_N);
  EXPECT_GT(half.Pz_N, 0.0);
}

TEST(LathePlant, FacingSwapsFeedAndDepth) {
  const auto c = config();
  LathePlant p;
  p.configure(c, {});
  // Face 1 mm off the end of the bar, feeding toward the axis at 0.2 mm/rev.
  (void)move(p, 25.0, 5.0, 25.0, -1.0 + 0.8, 1000.0, 1.0);  // position beside the face, in air
  const auto out = move(p, 25.0, -0.2, 10.0, -0.2, 1000.0, 0.2);
  EXPECT_NEAR(out.feed_per_rev_mm, 0.2, 1e-3);
  EXPECT_NEAR(out.depth_mm, 1.0, 0.02);  // the nose's lowest point is 1 mm into the bar
  const double v = std::numbers::pi * 2.0 * (10.0 + out.depth_mm) * 1000.0 / 1000.0;
  EXPECT_NEAR(out.Pz_N, handbook_pz(c, out.depth_mm, 0.2, v), 0.01 * out.Pz_N);
}

TEST(LathePlant, ASecondPassCutsOnlyWhatTheFirstLeft) {
  const auto c = config();
  LathePlant p;
  p.configure(c, {});
  (void)move(p, 18.0, 2.0, 18.0, -12.0, 800.0, 0.25);
  (void)move(p, 18.0, -12.0, 25.0, -12.0, 800.0, 5.0);  // retract through air
  (void)move(p, 25.0, -12.0, 25.0, 2.0, 800.0, 5.0);
  const auto out = move(p, 17.0, 2.0, 17.0, -10.0, 800.0, 0.25);
  // The first pass left its feed marks: cusps of height Rz = s²/(8r) above 18 mm.
  const double rz = 0.25 * 0.25 / (8.0 * c.cutting.nose_radius_mm);
  EXPECT_GT(out.depth_mm, 1.0);
  EXPECT_LT(out.depth_mm, 1.0 + rz);
}

TEST(LathePlant, RefusesABlankWithoutExtentAndBadGrids) {
  auto c = config();
  LathePlant p;
  EXPECT_THROW(p.configure(c, {.cell_mm = 0.0}), std::invalid_argument);
  EXPECT_THROW(p.configure(c, {.cell_mm = 1e-7}), std::invalid_argument);
  c.stock.blank_diameter_mm.resize(1);
  EXPECT_THROW(p.configure(c, {}), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::sim
