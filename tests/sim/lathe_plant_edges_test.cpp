// The insert's straight edges in the path-driven lathe plant against their closed form: a face
// deeper along z than the nose (2 r_n) is cut by the edge that leaves the nose at the back angle,
// x = x_t + (z_t − z)·tan β from its tangent point; the facing program of issue 47 with a 0.4 mm
// nose leaves no ring for the retract; turning a diameter gives what the nose alone gives, bit
// for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include "lathectl/cutting/lathe_plant.hpp"
#include "step_allowance_config.hpp"

namespace lathectl::sim {
using cutting::LathePlant;
namespace {

// Steps the tool from (x0, z0) to (x1, z1) at `feed` mm/rev, 1200 rpm, 1 ms steps, ending
// exactly at (x1, z1).
LathePlant::Output go(LathePlant& p, double x0, double z0, double x1, double z1, double feed) {
  const double rpm = 1200.0, dt = 1e-3;
  const double len = std::hypot(x1 - x0, z1 - z0);
  const int n = std::max(1, static_cast<int>(len / (feed * rpm / 60.0) / dt));
  LathePlant::Output out;
  for (int k = 1; k <= n; ++k) {
    const double f = static_cast<double>(k) / n;
    p.step({x0 + f * (x1 - x0), z0 + f * (z1 - z0), rpm}, dt, out);
  }
  return out;
}

// Q2 with a CNMG in a 95° holder, LinuxCNC's I85 J5 (AXIS: an edge at a runs along machine
// (x, z) = (sin a, cos a)): the 5° edge bounds the tool from below toward machine +z (stock −z);
// the 85° edge rises over the nose and cuts nothing the nose does not. No angles: the nose alone.
TEST(LathePlantEdges, ACnmgInA95DegreeHolderAtQ2) {
  const double r = 0.4, deg = std::numbers::pi / 180.0;
  const auto e = cutting::straight_edges_of(2, r, 85.0, 5.0, 12.9);
  const auto swapped = cutting::straight_edges_of(2, r, 5.0, 85.0, 12.9);
  ASSERT_TRUE(e[0].on);
  EXPECT_FALSE(e[1].on);
  EXPECT_EQ(e[0].side, -1);
  EXPECT_NEAR(e[0].slope, std::tan(5.0 * deg), 1e-12);
  EXPECT_NEAR(e[0].hx, r * (1.0 - std::cos(5.0 * deg)), 1e-12);
  EXPECT_NEAR(e[0].hz, -r * std::sin(5.0 * deg), 1e-12);
  EXPECT_NEAR(e[0].reach, 12.9 * std::cos(5.0 * deg), 1e-12);
  EXPECT_EQ(swapped[0].slope, e[0].slope);  // I and J in either order (AXIS: min and max)
  EXPECT_EQ(swapped[0].hz, e[0].hz);
  // Q1 (PCLNL, I95 J175) mirrors it toward stock +z.
  const auto q1 = cutting::straight_edges_of(1, r, 95.0, 175.0, 12.9);
  EXPECT_FALSE(q1[0].on);
  ASSERT_TRUE(q1[1].on);
  EXPECT_EQ(q1[1].side, 1);
  EXPECT_NEAR(q1[1].slope, e[0].slope, 1e-12);
  // LinuxCNC's sample lathe.tbl: Q6 I120 J60 has both (60° each side); Q3's edges run below the
  // nose (an internal tool) and Q7's along −x: none. No angles, Q9, a bad insert: none.
  const auto q6 = cutting::straight_edges_of(6, r, 120.0, 60.0, 12.9);
  EXPECT_TRUE(q6[0].on && q6[1].on);
  EXPECT_NEAR(q6[0].slope, std::tan(60.0 * deg), 1e-12);
  for (const auto& [q, i, j] : {std::tuple{3, 275.0, 335.0}, {7, -30.0, 30.0}, {2, 0.0, 0.0},
                                {9, 85.0, 5.0}, {2, 10.0, 200.0}})
    for (const auto& x : cutting::straight_edges_of(q, r, i, j, 12.9)) EXPECT_FALSE(x.on) << q;
}

// Issue 47's facing program with a 0.4 mm nose: the blank's face at machine Z1 (z_origin 1),
// faced 1 mm at Z0. The nose covers stock z 0.2–1.0; the 0.2 mm beyond it is the edge's. Each
// cell is the closed form min(arc, edge) at the tool's last position, and the volume removed is
// its integral within the grid's half cells at the face's ends; then the retract G0 Z2 meets no
// material. The nose alone (no edges) leaves the ring the retract ran into.
TEST(LathePlantEdges, AFaceDeeperThanTheNoseIsCutByTheEdge) {
  auto c = fixtures::step_allowance_config();
  const double r = 0.4, R = 20.0, xf = 10.0, deg = std::numbers::pi / 180.0;
  c.cutting.nose_radius_mm = r;
  c.tool_front_angle_deg = 85.0;  // a CNMG in a 95° holder
  c.tool_back_angle_deg = 5.0;
  LathePlant p;
  p.configure(c, {.z_origin_mm = 1.0});
  (void)go(p, R + 2.0, 2.0, R + 2.0, 0.0, 5.0);
  const auto faced = go(p, R + 2.0, 0.0, xf, 0.0, 0.2);
  const double zc = 0.6, m = std::tan(5.0 * deg);            // the nose centre's stock z
  const double zt = zc - r * std::sin(5.0 * deg);            // the edge's tangent point
  const double xt = xf + r * (1.0 - std::cos(5.0 * deg));
  auto law = [&](double u) {
    double x = R;
    if (std::abs(u - zc) <= r) x = std::min(x, xf + r - std::sqrt(r * r - (u - zc) * (u - zc)));
    if (u <= zt) x = std::min(x, xt + (zt - u) * m);
    return x;
  };
  for (int i = 0; i <= 110; ++i) {
    const double u = 0.01 * i;
    EXPECT_NEAR(p.radius_mm(u), law(u), 1e-9) << "stock z " << u;
  }
  EXPECT_NEAR(p.radius_mm(0.1), xt + (zt - 0.1) * m, 1e-9);  // 0.1 mm beyond the nose
  // ∫ π(R² − law²) dz over the face, closed form: the edge's part [0, z_t] and the arc's.
  const double a = xt + zt * m;  // the edge at z = 0
  const double edge_part = R * R * zt - (a * a * a - xt * xt * xt) / (3.0 * m);
  const double xc = xf + r;
  auto arc_sq = [&](double w) {  // ∫ (xc − √(r² − w²))² dw
    const double s = std::sqrt(r * r - w * w);
    return (xc * xc + r * r) * w - w * w * w / 3.0 - xc * (w * s + r * r * std::asin(w / r));
  };
  const double arc_part = R * R * (zc + r - zt) - (arc_sq(r) - arc_sq(zt - zc));
  const double volume = std::numbers::pi * (edge_part + arc_part);
  const double half_cells = std::numbers::pi * (R * R - xf * xf) * 0.01;
  EXPECT_NEAR(faced.removed_mm3, volume, half_cells);
  // To X−1 and back out along the axis: the retract meets nothing.
  const auto centre = go(p, xf, 0.0, -1.0, 0.0, 0.2);
  const auto out = go(p, -1.0, 0.0, -1.0, 2.0, 0.5);
  EXPECT_EQ(out.removed_mm3, centre.removed_mm3);
  EXPECT_FALSE(out.in_contact);
  // The nose alone leaves stock z 0–0.2 standing: the retract cuts it.
  LathePlant nose;
  nose.configure(c, {.z_origin_mm = 1.0, .edge_length_mm = 0.0});
  (void)go(nose, R + 2.0, 2.0, R + 2.0, 0.0, 5.0);
  const auto nose_centre = go(nose, R + 2.0, 0.0, -1.0, 0.0, 0.2);
  EXPECT_EQ(nose.radius_mm(0.1), R);
  EXPECT_GT(go(nose, -1.0, 0.0, -1.0, 2.0, 0.5).removed_mm3, nose_centre.removed_mm3 + 200.0);
}

// Turning toward the chuck (Q2 I85 J5, r 0.8): the trailing edge stays above the surface the nose's
// lowest point leaves, so every output is the nose alone's, bit for bit — into the bar from its
// end, along it, up a shoulder and out.
TEST(LathePlantEdges, TurningADiameterIsTheNoseAloneBitForBit) {
  auto c = fixtures::step_allowance_config();
  c.tool_front_angle_deg = 85.0;
  c.tool_back_angle_deg = 5.0;
  LathePlant edges, nose;
  edges.configure(c, {});
  nose.configure(c, {.edge_length_mm = 0.0});
  ASSERT_TRUE(edges.straight_edges()[0].on);
  const double path[][2] = {{25, 5}, {18, 5}, {18, -12}, {19, -12}, {19, 3}, {17, 3},
                            {17, -8}, {21, -8}, {25, 5}};
  LathePlant::Output a, b;
  for (std::size_t s = 0; s + 1 < std::size(path); ++s) {
    const auto [x0, z0] = path[s];
    const auto [x1, z1] = path[s + 1];
    const double len = std::hypot(x1 - x0, z1 - z0), v = 0.25 * 800.0 / 60.0;
    const int n = static_cast<int>(len / v / 1e-3);
    for (int k = 1; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      const LathePlant::Input in{x0 + f * (x1 - x0), z0 + f * (z1 - z0), 800.0};
      edges.step(in, 1e-3, a);
      nose.step(in, 1e-3, b);
      ASSERT_EQ(a.removed_mm3, b.removed_mm3) << s << " " << k;
      ASSERT_EQ(a.depth_mm, b.depth_mm) << s << " " << k;
      ASSERT_EQ(a.Pz_N, b.Pz_N) << s << " " << k;
      ASSERT_EQ(a.force_measured, b.force_measured) << s << " " << k;
    }
  }
  EXPECT_GT(a.removed_mm3, 1000.0);
}

// A tool change (set_tool: another nose and Q) derives the edges again for the new nose, the
// angles kept (set_edges); the edges are straight_edges_of that tool, and a plant configured
// with it from the start has the same.
TEST(LathePlantEdges, AToolChangeDerivesTheEdgesForItsNose) {
  auto c = fixtures::step_allowance_config();
  LathePlant p, q;
  p.configure(c, {.nose_radius_mm = 0.8, .orientation = 2, .max_nose_radius_mm = 0.8});
  p.set_edges(85.0, 5.0);
  p.set_tool(0.4, 1);
  q.configure(c, {.nose_radius_mm = 0.4, .orientation = 1, .front_angle_deg = 85.0,
                  .back_angle_deg = 5.0});
  const auto want = cutting::straight_edges_of(1, 0.4, 85.0, 5.0, cutting::kDefaultEdgeLengthMm);
  for (std::size_t k = 0; k < 2; ++k) {
    for (const auto* g : {&p.straight_edges()[k], &q.straight_edges()[k]}) {
      EXPECT_EQ(g->on, want[k].on) << k;
      EXPECT_EQ(g->side, want[k].side) << k;
      EXPECT_EQ(g->slope, want[k].slope) << k;
      EXPECT_EQ(g->hx, want[k].hx) << k;
      EXPECT_EQ(g->hz, want[k].hz) << k;
      EXPECT_EQ(g->reach, want[k].reach) << k;
    }
  }
  p.set_tool(0.8, 2);
  EXPECT_EQ(p.straight_edges()[0].hx, cutting::straight_edges_of(2, 0.8, 85.0, 5.0, 12.9)[0].hx);
}

}  // namespace
}  // namespace lathectl::sim
