// The path-driven lathe plant (the LinuxCNC plant component's model) against closed forms:
// steady longitudinal turning removes t·s per revolution and gives the handbook force at the
// uncut diameter; facing swaps the roles (s radial, t axial); the first revolution builds the
// chip up; the workpiece keeps what earlier passes cut (with their feed marks); bad stock is
// refused.

#include "lathectl/cutting/lathe_plant.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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
  p.configure(c, {.orientation = 6});  // the nose's lowest point under its centre programmed
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
  p.configure(c, {.orientation = 6});  // Q6: the programmed point is the nose's lowest point
  // Face 1 mm off the end of the bar, feeding toward the axis at 0.2 mm/rev.
  (void)move(p, 25.0, 5.0, 25.0, -1.0 + 0.8, 1000.0, 1.0);  // position beside the face, in air
  const auto out = move(p, 25.0, -0.2, 10.0, -0.2, 1000.0, 0.2);
  EXPECT_NEAR(out.feed_per_rev_mm, 0.2, 1e-3);
  EXPECT_NEAR(out.depth_mm, 1.0, 0.02);  // the nose's lowest point is 1 mm into the bar
  const double v = std::numbers::pi * 2.0 * (10.0 + out.depth_mm) * 1000.0 / 1000.0;
  EXPECT_NEAR(out.Pz_N, handbook_pz(c, out.depth_mm, 0.2, v), 0.01 * out.Pz_N);
}

// A 3 mm grooving insert (Input::insert_width_mm) plunged at 0.05 mm/rev beside the nose alone
// on the same path: the same stock, chip and speed, and at every step the cutting law at the
// insert's width and the feed per revolution (the law lathectl optimize and the LinuxCNC plant
// share), not at the nose's engagement.
TEST(LathePlant, AGroovingInsertCutsItsWholeWidth) {
  const auto c = config();
  LathePlant nose, insert;
  nose.configure(c, {});
  insert.configure(c, {});
  cutting::CuttingModel law;
  law.configure(c.cutting);
  cutting::Disturbances wear;
  wear.configure(c.disturbances);
  const double dt = 1e-3, rpm = 800.0, feed = 0.05;
  const auto n = static_cast<int>(3.0 / (feed * rpm / 60.0) / dt);  // x 21 → 18 at z −6
  LathePlant::Output a, b;
  int cut = 0;
  for (int k = 1; k <= n; ++k) {
    const double x = 21.0 - 3.0 * k / n;
    const double t_before = b.time_in_cut_s;
    nose.step({x, -6.0, rpm}, dt, a);
    insert.step({.x_mm = x, .z_mm = -6.0, .rpm = rpm, .insert_width_mm = 3.0}, dt, b);
    ASSERT_EQ(b.depth_mm, a.depth_mm);
    ASSERT_EQ(b.feed_per_rev_mm, a.feed_per_rev_mm);
    ASSERT_EQ(b.removed_mm3, a.removed_mm3);
    if (!(b.depth_mm > 0.0 && b.feed_per_rev_mm > 0.0)) continue;
    ++cut;
    const auto f = law.forces({3.0, b.feed_per_rev_mm, b.speed_m_per_min, b.strength_factor,
                               wear.wear_factor(t_before)});
    ASSERT_DOUBLE_EQ(b.Pz_N, f.Pz) << k;
    ASSERT_DOUBLE_EQ(b.Py_N, f.Py) << k;
  }
  EXPECT_GT(cut, n / 2);
  EXPECT_NEAR(b.feed_per_rev_mm, feed, 1e-3);
  // The nose (r 0.8) meets the groove's bottom about 1.6 mm wide: the insert's 3 mm cut is
  // the stronger.
  EXPECT_GT(b.Pz_N, 1.3 * a.Pz_N);
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

// Faces and shoulders are part of the radius profile R(z): what a facing cut removed stays
// removed. The user's facing (0.5 mm off the end, down past the axis to x = −0.5) leaves, over
// the nose's reach, R(z') = max(0, x + r − √(r² − (z' − z)²)) (the nose's circle, its lowest
// point at the controlled point: orientation Q6, as FacingSwapsFeedAndDepth); the retract along
// the axis (machine +z, out of the part) removes nothing; and the next cut over the faced end
// meets material first where the nose's circle reaches the untouched bar at z + r.
TEST(LathePlant, AFacedEndStaysFacedForTheMovesAfterIt) {
  const auto c = config();
  const double r = c.cutting.nose_radius_mm;
  const double R = 0.5 * c.stock.blank_diameter_mm.front().value;
  LathePlant p;
  p.configure(c, {.orientation = 6});
  const double zf = -0.5;  // machine z of the facing cut: stock z 0.5
  (void)move(p, R + 2.0, 5.0, R + 2.0, zf, 1000.0, 5.0);
  (void)move(p, R + 2.0, zf, -0.5, zf, 1000.0, 0.15);
  for (const double zs : {0.0, 0.3, 0.5, 0.9, 1.2, 1.29}) {
    const double dz = zs - 0.5;
    const double expected = std::max(0.0, -0.5 + r - std::sqrt(std::max(r * r - dz * dz, 0.0)));
    EXPECT_NEAR(p.radius_mm(zs), expected, 0.02) << "stock z " << zs;
  }
  EXPECT_NEAR(p.radius_mm(0.5 + r + 0.05), R, 1e-9);  // beyond the nose's reach: the bar
  LathePlant::Output out;
  p.step({-0.5, zf, 1000.0}, 1e-3, out);
  const double removed = out.removed_mm3;
  const auto back = move(p, -0.5, zf, -0.5, 2.0, 1000.0, 5.0);  // G0 Z2
  EXPECT_DOUBLE_EQ(back.removed_mm3, removed);
  EXPECT_FALSE(back.in_contact);
  // A pass 1 mm deep toward −z from Z2: first contact where z_tool + r reaches the bar's
  // untouched material at stock z 0.5 + r, i.e. at stock z 0.5 (machine z −0.5).
  (void)move(p, -0.5, 2.0, R - 1.0, 2.0, 1000.0, 5.0);
  double first = std::nan("");
  const double dt = 1e-3, v = 0.2 * 1000.0 / 60.0;
  for (double z = 2.0; z > -3.0; z -= v * dt) {
    p.step({R - 1.0, z, 1000.0}, dt, out);
    if (out.removed_mm3 > removed + 1e-9) {
      first = z;
      break;
    }
  }
  EXPECT_NEAR(first, zf, 0.02);
}

// The programmed point is the imaginary tool tip of LinuxCNC's orientation Q (rs274ngc's
// latheorigin_x/z): a facing cut at machine z_f down to x_f removes the band of the nose's
// circle centred at z_f + q_z·r (stock z_origin − that), and leaves the band's middle at the
// nose's lowest point, x_f + (q_x − 1)·r. Q2, the scenarios' default: the diameter is x_f, the
// face the nose's leading point at z_f itself (the part toward −z is untouched from z_f on).
TEST(LathePlant, TheProgrammedPointIsTheToolTipOfTheOrientation) {
  auto c = config();
  const double r = c.cutting.nose_radius_mm;
  const double R = 0.5 * c.stock.blank_diameter_mm.front().value;
  EXPECT_EQ(c.tool_orientation, 2);
  for (int q = 0; q <= 9; ++q) {
    c.tool_orientation = q;
    LathePlant p;
    p.configure(c, {.z_origin_mm = 1.0});
    EXPECT_EQ(p.orientation(), q);
    const cutting::NoseOffset o = cutting::nose_centre_offset(q);
    const double zf = -2.0, xf = R - 3.0;  // stock z 3, 3 mm below the bar's radius
    (void)move(p, R + 2.0, zf, xf, zf, 1000.0, 0.2);
    const double zc = 1.0 - (zf + o.z * r);  // the nose centre's stock z
    const double low = xf + (o.x - 1) * r;
    EXPECT_NEAR(p.radius_mm(zc), low, 1e-4) << "Q" << q;  // the cell nearest the centre
    EXPECT_NEAR(p.radius_mm(zc + r + 0.02), R, 1e-9) << "Q" << q;
    EXPECT_NEAR(p.radius_mm(zc - r - 0.02), R, 1e-9) << "Q" << q;
    EXPECT_NEAR(p.nose_centre_stock_z_mm(zf), zc, 1e-12);
    EXPECT_NEAR(p.nose_low_x_mm(xf), low, 1e-12);
  }
  c.tool_orientation = 2;  // the face: at machine z_f − 0.01 the bar, at z_f + 0.01 cut
  LathePlant p;
  p.configure(c, {.z_origin_mm = 1.0});
  (void)move(p, R + 2.0, 0.0, -0.2, 0.0, 1000.0, 0.2);
  EXPECT_NEAR(p.radius_mm(p.stock_z_mm(-0.01)), R, 1e-9);
  EXPECT_LE(p.radius_mm(p.stock_z_mm(0.01)), -0.2 + r);  // under the nose's leading arc
  EXPECT_EQ(p.radius_mm(p.stock_z_mm(0.5)), 0.0);
  c.tool_orientation = 10;
  EXPECT_THROW(p.configure(c, {}), std::invalid_argument);
  // A change of tool (set_orientation) moves the nose, not the workpiece.
  p.set_orientation(9);
  EXPECT_EQ(p.orientation(), 9);
  EXPECT_NEAR(p.nose_low_x_mm(5.0), 5.0 - r, 1e-12);
}

// A change of tool (set_tool: the nose and Q of the tool table's tool in the spindle) cuts as a
// plant configured with that nose cuts: the same numbers. The workpiece stays; a nose beyond
// Params::max_nose_radius_mm is the largest.
TEST(LathePlant, AToolChangeCutsAsAPlantOfThatNose) {
  const auto c = config();
  const double R = 0.5 * c.stock.blank_diameter_mm.front().value;
  LathePlant a, b;
  a.configure(c, {.nose_radius_mm = 0.4, .orientation = 6});
  b.configure(c, {.max_nose_radius_mm = 1.6});
  b.set_tool(0.4, 6);
  EXPECT_EQ(b.nose_radius_mm(), 0.4);
  EXPECT_EQ(b.orientation(), 6);
  const auto oa = move(a, R - 2.0, 2.0, R - 2.0, -10.0, 1000.0, 0.3);
  const auto ob = move(b, R - 2.0, 2.0, R - 2.0, -10.0, 1000.0, 0.3);
  EXPECT_EQ(oa.Pz_N, ob.Pz_N);
  EXPECT_EQ(oa.removed_mm3, ob.removed_mm3);
  for (double z = 0.0; z < 12.0; z += 0.013) EXPECT_EQ(a.radius_mm(z), b.radius_mm(z)) << z;
  b.set_tool(5.0, 2);
  EXPECT_EQ(b.nose_radius_mm(), 1.6);
  EXPECT_NEAR(b.radius_mm(5.0), R - 2.0, 1e-9);
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

namespace lathectl::sim {
namespace {
bool same(const LathePlant::Output& a, const LathePlant::Output& b) {
  return a.removed_mm3 == b.removed_mm3 && a.chip_depth_mm == b.chip_depth_mm &&
         a.feed_per_rev_mm == b.feed_per_rev_mm && a.engaged_depth_mm == b.engaged_depth_mm &&
         a.on_blank == b.on_blank;
}
}  // namespace

// A plant following another (rig E's stock model and its plant) takes the leader's cut where it
// is cut at the leader's position just after it, and gives what cutting its own grid gives; once
// out of step (another position) it cuts its own grid, still the same numbers as a plant alone.
// An eccentric blank: the chip is t + e·sin φ, whose mean over whole revolutions is the
// geometry's t, whatever the simulation step. (A step travels less than a cell; one that took no
// new cell at the nose's front read the nose's own last cut as an earlier pass's surface and
// clipped the runout's upper half: here 1.79 mm at 1 ms, 1.71 mm at 0.25 ms.)
TEST(LathePlant, AnEccentricBlanksChipAveragesToItsGeometryAtAnyStep) {
  auto c = config();
  c.stock.eccentricity_mm = 1.0;
  c.disturbances.random_sigma_mm = 0.0;
  for (double dt : {1e-3, 2.5e-4}) {
    LathePlant p;
    p.configure(c, {.nose_radius_mm = 1.2});  // x + r_n above the blank's low side R − e
    // 40 mm bar at x = 18 (t = 2) at 0.25 mm/rev and 800 rpm, toward −z from z = +2; the mean
    // over the last 10 revolutions of the 12 mm.
    const double rpm = 800.0, v = 0.25 * rpm / 60.0;
    const auto n = static_cast<int>(14.0 / v / dt);
    const auto last = static_cast<int>(10.0 * 60.0 / rpm / dt);
    double depth = 0.0, chip = 0.0;
    LathePlant::Output out;
    for (int k = 1; k <= n; ++k) {
      p.step({18.0, 2.0 - 14.0 * k / n, rpm}, dt, out);
      if (k > n - last) {
        depth += out.depth_mm / last;
        chip += out.chip_depth_mm / last;
      }
    }
    EXPECT_NEAR(chip, 2.0, 2e-3) << dt;
    EXPECT_NEAR(depth, 2.0, 5e-3) << dt;
  }
}

// A pass at the eccentric blank's mean radius cuts its high side: a later pass meets the surface
// min(R + e·sin φ, R), a chip of mean (R − x) − e/π, not the blank's full runout.
TEST(LathePlant, APassAtTheBlanksMeanRadiusCutsItsHighSideForTheNext) {
  auto c = config();
  c.stock.eccentricity_mm = 1.0;
  c.disturbances.random_sigma_mm = 0.0;
  LathePlant p;
  p.configure(c, {.nose_radius_mm = 1.2});
  (void)move(p, 20.0, 2.0, 20.0, -12.0, 800.0, 0.25);  // x = R = 20: no chip by the geometry
  (void)move(p, 20.0, -12.0, 25.0, -12.0, 800.0, 5.0);  // out, back and down in air
  (void)move(p, 25.0, -12.0, 25.0, 2.0, 800.0, 5.0);
  (void)move(p, 25.0, 2.0, 18.0, 2.0, 800.0, 5.0);
  const auto m = move_mean(p, 18.0, 2.0, -12.0, 800.0, 0.25);
  EXPECT_NEAR(m.depth, 2.0 - 1.0 / std::numbers::pi, 5e-3);  // was 2.0: the full runout
}

TEST(LathePlant, AFollowerGivesWhatItsOwnCutGivesInStepOrNot) {
  LathePlant leader, follower, alone;
  for (auto* p : {&leader, &follower, &alone}) p->configure(config(), {});
  follower.follow(&leader);
  LathePlant::Output lo, fo, ao;
  double removed = 0.0;
  for (int k = 0; k < 4000; ++k) {  // turning at x = 18 into the bar from z = +1 toward −z
    const double z = 1.0 - 0.005 * k;
    const bool apart = k >= 3000;  // the leader cuts 0.1 mm lower from here on
    leader.step({apart ? 17.9 : 18.0, z, 1200.0}, 1e-3, lo);
    follower.cut({18.0, z, 1190.0}, 1e-3, fo);
    alone.cut({18.0, z, 1190.0}, 1e-3, ao);
    ASSERT_TRUE(same(fo, ao)) << k;
    ASSERT_EQ(follower.following(), !apart) << k;
    ASSERT_EQ(follower.max_radius_mm(-1e9, 1e9), alone.max_radius_mm(-1e9, 1e9)) << k;
    removed = fo.removed_mm3;
  }
  EXPECT_GT(removed, 0.0);
  EXPECT_NE(lo.removed_mm3, fo.removed_mm3);  // the leader cut deeper: apart indeed
  // A follower whose workpiece is not the leader's now is refused.
  LathePlant fresh;
  fresh.configure(config(), {});
  EXPECT_THROW(fresh.follow(&leader), std::invalid_argument);
}

}  // namespace lathectl::sim
