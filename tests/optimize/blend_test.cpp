// LinuxCNC's G64 blend arcs (src/optimize/blend.hpp) against what LinuxCNC 2.9 did in the
// simulated lathe (scripts/linuxcnc-sim, hal/config/lathectl-lathe.ini: 500 mm/s², 80 mm/s),
// recorded from motion's position at the servo period on examples/linuxcnc/profile_arcs.ngc's
// optimised program (2026-11-24; circles through the recorded blend points: 1198 and 2242 points,
// all within 1e-4 mm of them), and against the closed forms of the geometry.
#include "optimize/blend.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "lathectl/io/canon.hpp"
#include "optimize/path.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

CanonMove line(double x0, double z0, double x1, double z1, bool rapid = false) {
  CanonMove m;
  m.kind = rapid ? CanonMove::Kind::Traverse : CanonMove::Kind::Line;
  m.x0 = x0, m.z0 = z0, m.x1 = x1, m.z1 = z1;
  m.per_rev = true;
  m.feed = 0.2;
  m.spindle_on = true;
  m.speed = 1194.0;
  return m;
}
CanonMove arc(double x0, double z0, double x1, double z1, double xc, double zc, int rotation) {
  CanonMove m = line(x0, z0, x1, z1);
  m.kind = CanonMove::Kind::Arc;
  m.xc = xc, m.zc = zc, m.rotation = rotation;
  return m;
}
Corner corner(const CanonMove& a, const CanonMove& b) {
  return blend_corner({&a, 0.0, 1.0, move_length(a)}, {&b, 0.0, 1.0, move_length(b)}, Machine{});
}
// The corner a → b when `in` came before a: a keeps what the blend in → a left of it, as
// LinuxCNC trims it before it plans the next corner.
Corner corner_after(const CanonMove& in, const CanonMove& a, const CanonMove& b) {
  const Corner first = corner(in, a);
  EXPECT_TRUE(first.blended);
  return blend_corner({&a, 0.0, 1.0, move_length(a) - first.trim_start_mm},
                      {&b, 0.0, 1.0, move_length(b)}, Machine{});
}
// The largest distance of the blend arc from the programmed corner point P.
double inside_at_corner(const Corner& c, double xp, double zp) {
  const double r = std::hypot(c.arc.x0 - c.arc.xc, c.arc.z0 - c.arc.zc);
  return std::hypot(xp - c.arc.xc, zp - c.arc.zc) - r;
}

// profile_arcs.ngc: "G1 Z-8" from X16 Z2, then "G2 X18 Z-20 R10" (centre X24.829 Z-12.695): a
// 28° corner. LinuxCNC's blend was the circle centred at X−1.482 Z−4.759, R 17.482: it left the
// line 3.24 mm before the corner and passed 0.30 mm inside it.
TEST(Blend, LineIntoArcIsWhereLinuxCncCut) {
  const auto a = line(16, 2, 16, -8);
  const auto b = arc(16, -8, 18, -20, 24.829259, -12.695123, -1);
  const Corner c = corner(a, b);
  ASSERT_TRUE(c.blended);
  EXPECT_NEAR(c.arc.xc, -1.482, 0.02);
  EXPECT_NEAR(c.arc.zc, -4.759, 0.02);
  EXPECT_NEAR(std::hypot(c.arc.x0 - c.arc.xc, c.arc.z0 - c.arc.zc), 17.482, 0.02);
  EXPECT_NEAR(c.trim_end_mm, 3.24, 0.02);
  EXPECT_NEAR(inside_at_corner(c, 16, -8), 0.30, 0.01);
  // The blend arc is tangent to the line where it leaves it: its centre level with that point.
  EXPECT_NEAR(c.arc.z0, c.arc.zc, 1e-9);
  EXPECT_NEAR(c.arc.x0, 16.0, 1e-9);
  // …and to the G2's circle: the centres are R_blend + 10 apart (outside it, a concave corner).
  const double rb = std::hypot(c.arc.x0 - c.arc.xc, c.arc.z0 - c.arc.zc);
  EXPECT_NEAR(std::hypot(c.arc.xc - b.xc, c.arc.zc - b.zc), rb + 10.0, 1e-6);
}

// The same program's "G2 … Z-20" into "G1 Z-32" (a 47° corner): LinuxCNC's blend was the circle
// centred at X4.177 Z−24.570, R 13.823: it met the line 4.57 mm after the corner and passed
// 0.74 mm inside it.
TEST(Blend, ArcIntoLineIsWhereLinuxCncCut) {
  const auto in = line(16, 2, 16, -8);  // the G1 Z-8 whose blend trims the G2's start
  const auto a = arc(16, -8, 18, -20, 24.829259, -12.695123, -1);
  const auto b = line(18, -20, 18, -32);
  const Corner c = corner_after(in, a, b);
  ASSERT_TRUE(c.blended);
  EXPECT_NEAR(c.arc.xc, 4.177, 0.02);
  EXPECT_NEAR(c.arc.zc, -24.570, 0.02);
  EXPECT_NEAR(std::hypot(c.arc.x1 - c.arc.xc, c.arc.z1 - c.arc.zc), 13.823, 0.02);
  EXPECT_NEAR(c.trim_start_mm, 4.57, 0.02);
  EXPECT_NEAR(c.arc.x1, 18.0, 1e-9);  // tangent to the line where it meets it
  EXPECT_NEAR(c.arc.z1, c.arc.zc, 1e-9);
  EXPECT_NEAR(inside_at_corner(c, 18, -20), 0.74, 0.01);
}

// Two rapids at 90° ("G0 X25" 6.5 mm, then "G0 Z2"): blendInit3FromLineLine takes half the
// shorter (3.25 mm) within the quarter-length tolerance (d_tol = 1.625·cos45°/(1 − sin45°) =
// 3.92 mm), so R = tan45°·3.25 and v_plan = √(a_n·R) = √(500·√0.75·3.25) = 37.5 mm/s; LinuxCNC
// ran the corner at 37.51 mm/s, leaving the X move at x 22.0.
TEST(Blend, RapidCornerRadiusAndSpeed) {
  const auto a = line(18.5, -50, 25, -50, true);
  const auto b = line(25, -50, 25, 2, true);
  const Corner c = corner(a, b);
  ASSERT_TRUE(c.blended);
  EXPECT_NEAR(c.trim_end_mm, 3.25, 1e-9);
  EXPECT_NEAR(c.trim_start_mm, 3.25, 1e-9);
  EXPECT_NEAR(std::hypot(c.arc.x0 - c.arc.xc, c.arc.z0 - c.arc.zc), 3.25, 1e-9);
  EXPECT_NEAR(c.v_max_mm_s, std::sqrt(500.0 * std::sqrt(0.75) * 3.25), 1e-9);
  EXPECT_NEAR(c.v_max_mm_s, 37.51, 0.05);
}

// G94 at F400 (lathe_g70_71_demo.ngc's G71 passes): an unsynchronised block's blend is sized for
// its feed, 6.67 mm/s: R = max(v²/a_n, v²/(a/2)/φ) = 0.113 mm, so a 90° corner is passed
// R(√2 − 1) = 0.047 mm inside; LinuxCNC passed 0.0471 mm from the corner of "G1 Z-18.982" →
// "G1 X9.6536" at 6.67 mm/s (scripts/linuxcnc-sim, pawn_bar.toml, 2026-11-24). The same program's
// 30 rapid → feed and 30 feed → rapid corners all passed within 5 µm of the corner (not blended:
// predict.cpp leaves them alone).
TEST(Blend, FeedPerMinuteCornerIsSizedForTheFeed) {
  auto a = line(8, -11.232, 8, -18.982);
  auto b = line(8, -18.982, 9.6536, -18.982);
  for (auto* m : {&a, &b}) {
    m->per_rev = false;
    m->feed = 400.0;
  }
  const Corner c = corner(a, b);
  ASSERT_TRUE(c.blended);
  EXPECT_NEAR(c.v_max_mm_s, 400.0 / 60.0, 1e-9);
  EXPECT_NEAR(inside_at_corner(c, 8, -18.982), 0.0471, 0.001);
}

// Arc into arc (blendInit3FromArcArc): "G3 X36 Z-6 I0 K-6" from X30 Z0 (R 6), then
// "G2 X36 Z-18 I6 K-6" (R 8.49), a 45° corner at F0.3 mm/rev, 1194 rpm, in air. LinuxCNC's
// blend was the circle centred at X34.1214 Z−5.3462, R 1.8271 (243 recorded positions within
// 1e-5 mm of it), 0.162 mm inside the corner.
TEST(Blend, ArcIntoArcIsWhereLinuxCncCut) {
  const auto in = line(30, 5, 30, 0);  // "G1 Z0": its blend into the G3 trims the G3's start
  const auto a = arc(30, 0, 36, -6, 30, -6, 1);
  const auto b = arc(36, -6, 36, -18, 42, -12, -1);
  const Corner c = corner_after(in, a, b);
  ASSERT_TRUE(c.blended);
  EXPECT_NEAR(c.arc.xc, 34.1214, 0.01);
  EXPECT_NEAR(c.arc.zc, -5.3462, 0.01);
  EXPECT_NEAR(std::hypot(c.arc.x0 - c.arc.xc, c.arc.z0 - c.arc.zc), 1.8271, 0.01);
  EXPECT_NEAR(inside_at_corner(c, 36, -6), 0.162, 0.005);
}

// G64 P0.02: the arc stays within 0.02 mm of the corner (tcFindBlendTolerance).
TEST(Blend, ToleranceBoundsTheDeviation) {
  auto a = line(16, 2, 16, -8);
  auto b = arc(16, -8, 18, -20, 24.829259, -12.695123, -1);
  a.blend_tol_mm = b.blend_tol_mm = 0.02;
  const Corner c = corner(a, b);
  ASSERT_TRUE(c.blended);
  EXPECT_LE(inside_at_corner(c, 16, -8), 0.02 + 1e-9);
  EXPECT_GT(inside_at_corner(c, 16, -8), 0.01);
}

// Collinear pieces of a split move, and a reversal, are not blended.
TEST(Blend, TangentAndReversalAreNotBlended) {
  EXPECT_FALSE(corner(line(18.5, 2, 18.5, -12), line(18.5, -12, 18.5, -30)).blended);
  EXPECT_FALSE(corner(line(18.5, 2, 18.5, -12), line(18.5, -12, 18.5, 0)).blended);
}

// The canon reader keeps the blending mode and the commands LinuxCNC stops for.
TEST(Blend, CanonKeepsModesAndStops) {
  const auto p = io::parse_canon(R"(    1 N..... SELECT_PLANE(CANON_PLANE_XZ)
    2 N..... STRAIGHT_FEED(25.0000, 0.0000, -50.0000, 0.0000, 0.0000, 0.0000)
    3 N..... SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.020000)
    4 N..... STRAIGHT_FEED(20.0000, 0.0000, -50.0000, 0.0000, 0.0000, 0.0000)
    5 N..... DWELL(0.5000)
    6 N..... SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)
    7 N..... STRAIGHT_FEED(20.0000, 0.0000, -60.0000, 0.0000, 0.0000, 0.0000)
)",
                                 "t.ngc", 25.0, 5.0);
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_DOUBLE_EQ(p.moves[0].blend_tol_mm, 0.0);
  EXPECT_TRUE(p.moves[0].stop_before);  // from rest
  EXPECT_DOUBLE_EQ(p.moves[1].blend_tol_mm, 0.02);
  EXPECT_FALSE(p.moves[1].stop_before);
  EXPECT_LT(p.moves[2].blend_tol_mm, 0.0);
  EXPECT_TRUE(p.moves[2].stop_before);
}

}  // namespace
}  // namespace lathectl::optimize
