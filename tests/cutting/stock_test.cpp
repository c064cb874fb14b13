// Stock and roughing passes (system E) against the definitions in
// include/lathectl/cutting/stock.hpp:
//   D_prev(z) = smallest D_j of the earlier passes covering z, else the blank D_b(z)
//   t(k, z, φ) = max(0, (D_prev(z) − D_k)/2 + e·sin φ [blank surface only])
//   volume to remove = Σ_k ∫ π/4·(D_prev(z)² − D_k²) dz   (cylinder / annulus: π/4·(D² − d²)·L)
// The part is the stepped shaft of examples/scenarios/e_stepped_*.toml.

#include "lathectl/cutting/stock.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::cutting {
namespace {

constexpr double kPi = std::numbers::pi;

// Ø90 blank over z ∈ [0, 150], tapering linearly to Ø84 over [150, 152], Ø84 to z = 300;
// passes: Ø80 over [0, 300], then Ø74 and Ø70 over [150, 300].
StockParams stepped(double e = 1.0) {
  StockParams p;
  p.blank_diameter_mm = {{0.0, 90.0}, {150.0, 90.0}, {152.0, 84.0}, {300.0, 84.0}};
  p.eccentricity_mm = e;
  p.passes = {{0.0, 300.0, 80.0}, {150.0, 300.0, 74.0}, {150.0, 300.0, 70.0}};
  return p;
}

Stock make(const StockParams& p) {
  Stock s;
  s.configure(p);
  return s;
}

TEST(Stock, BlankDiameterIsPiecewiseLinearAndHeldOutside) {
  const Stock s = make(stepped());
  EXPECT_DOUBLE_EQ(s.blank_diameter_mm(-10.0), 90.0);
  EXPECT_DOUBLE_EQ(s.blank_diameter_mm(75.0), 90.0);
  EXPECT_DOUBLE_EQ(s.blank_diameter_mm(150.5), 88.5);
  EXPECT_DOUBLE_EQ(s.blank_diameter_mm(151.0), 87.0);
  EXPECT_DOUBLE_EQ(s.blank_diameter_mm(200.0), 84.0);
  EXPECT_DOUBLE_EQ(s.blank_diameter_mm(400.0), 84.0);
}

TEST(Stock, FirstPassCutsTheBlank) {
  const Stock s = make(stepped(0.0));
  EXPECT_DOUBLE_EQ(s.depth_mm(0, 50.0, 0.3), 5.0);   // (90 − 80)/2
  EXPECT_DOUBLE_EQ(s.depth_mm(0, 151.0, 0.3), 3.5);  // (87 − 80)/2 on the taper
  EXPECT_DOUBLE_EQ(s.depth_mm(0, 200.0, 0.3), 2.0);  // (84 − 80)/2
  EXPECT_DOUBLE_EQ(s.depth_mm(0, 300.0, 0.3), 2.0);  // z_end is inside the pass
  EXPECT_EQ(s.depth_mm(0, -0.1, 0.3), 0.0);
  EXPECT_EQ(s.depth_mm(0, 300.1, 0.3), 0.0);
  EXPECT_TRUE(s.blank_surface(0, 200.0));
  EXPECT_DOUBLE_EQ(s.surface_diameter_mm(0, 50.0), 90.0);
}

TEST(Stock, LaterPassesCutWhatEarlierPassesLeft) {
  const Stock s = make(stepped(0.0));
  // pass 1 meets the Ø80 of pass 0, pass 2 the Ø74 of pass 1
  EXPECT_DOUBLE_EQ(s.surface_diameter_mm(1, 200.0), 80.0);
  EXPECT_DOUBLE_EQ(s.depth_mm(1, 200.0, 0.0), 3.0);  // (80 − 74)/2
  EXPECT_DOUBLE_EQ(s.surface_diameter_mm(2, 200.0), 74.0);
  EXPECT_DOUBLE_EQ(s.depth_mm(2, 200.0, 0.0), 2.0);  // (74 − 70)/2
  EXPECT_DOUBLE_EQ(s.depth_mm(2, 151.0, 0.0), 2.0);  // the taper was cut by pass 0
  EXPECT_FALSE(s.blank_surface(1, 200.0));
  EXPECT_FALSE(s.blank_surface(2, 200.0));
  // outside the later passes' range: nothing
  EXPECT_EQ(s.depth_mm(1, 100.0, 0.0), 0.0);
  EXPECT_EQ(s.depth_mm(2, 149.9, 0.0), 0.0);
  EXPECT_EQ(s.depth_mm(3, 200.0, 0.0), 0.0);  // no such pass
}

TEST(Stock, SmallestEarlierDiameterWinsWhenPassesOverlap) {
  // Ø80 over [0, 60], then Ø85 over [0, 100]: in front of pass 2 the surface is the smallest
  // diameter of the earlier passes covering z, and the Ø85 pass cuts air where Ø80 was turned.
  StockParams p;
  p.blank_diameter_mm = {{0.0, 90.0}};
  p.passes = {{0.0, 60.0, 80.0}, {0.0, 100.0, 85.0}, {0.0, 150.0, 78.0}};
  const Stock s = make(p);
  EXPECT_DOUBLE_EQ(s.surface_diameter_mm(2, 30.0), 80.0);  // min(Ø80, Ø85)
  EXPECT_DOUBLE_EQ(s.surface_diameter_mm(2, 80.0), 85.0);
  EXPECT_DOUBLE_EQ(s.surface_diameter_mm(2, 120.0), 90.0);
  EXPECT_EQ(s.depth_mm(1, 30.0, 0.0), 0.0);  // Ø85 pass over a Ø80 surface: air
  EXPECT_DOUBLE_EQ(s.depth_mm(1, 80.0, 0.0), 2.5);
}

TEST(Stock, EccentricityOnlyOnTheBlankSurface) {
  const double e = 1.0;
  const Stock s = make(stepped(e));
  // first pass on the blank: t = 5 + e·sin φ
  for (double phi : {0.0, 0.5, kPi / 2, kPi, 1.5 * kPi, 5.0})
    EXPECT_NEAR(s.depth_mm(0, 50.0, phi), 5.0 + e * std::sin(phi), 1e-12) << phi;
  // later passes on a turned (concentric) surface: no eccentricity
  for (double phi : {0.0, kPi / 2, 1.5 * kPi}) {
    EXPECT_DOUBLE_EQ(s.depth_mm(1, 200.0, phi), 3.0) << phi;
    EXPECT_DOUBLE_EQ(s.depth_mm(2, 200.0, phi), 2.0) << phi;
  }
  // where a later pass reaches beyond the earlier ones it meets the blank again
  StockParams p = stepped(e);
  p.passes = {{0.0, 100.0, 80.0}, {0.0, 200.0, 80.0}};
  const Stock s2 = make(p);
  EXPECT_DOUBLE_EQ(s2.depth_mm(1, 50.0, kPi / 2), 0.0);  // Ø80 on Ø80
  EXPECT_TRUE(s2.blank_surface(1, 150.0));
  EXPECT_NEAR(s2.depth_mm(1, 120.0, kPi / 2), 5.0 + e, 1e-12);
}

// Regression (found by this test, fixed; src/cutting/stock.cpp, Stock::blank_surface): an earlier
// pass "covers" z as soon as z lies in its range, even when its diameter is above the (eccentric)
// blank there and it cut only air. Here pass 0 (Ø88) touches the Ø90 section but not the Ø84 one
// (84 + 2e = 86 < 88), so at z = 200 pass 1 still meets the untouched eccentric blank: t = (84 −
// 80)/2 + e·sin φ. The stock drops the runout (t = 2 for every φ), so the rig under-states the
// force swing there. Expected: a pass whose diameter is ≥ D_b(z) + 2e leaves the blank surface as
// it was.
TEST(Stock, PassThatCutOnlyAirLeavesTheEccentricBlank) {
  const double e = 1.0;
  StockParams p = stepped(e);
  p.passes = {{0.0, 300.0, 88.0}, {0.0, 300.0, 80.0}};
  const Stock s = make(p);
  EXPECT_EQ(s.depth_mm(0, 200.0, kPi / 2), 0.0);  // pass 0 is in air over the Ø84 section
  EXPECT_TRUE(s.blank_surface(1, 200.0));
  EXPECT_NEAR(s.depth_mm(1, 200.0, kPi / 2), 2.0 + e, 1e-12);
  EXPECT_NEAR(s.depth_mm(1, 200.0, 1.5 * kPi), 2.0 - e, 1e-12);
}

TEST(Stock, EccentricityNeverMakesDepthNegative) {
  StockParams p;
  p.blank_diameter_mm = {{0.0, 81.0}};
  p.eccentricity_mm = 1.0;
  p.passes = {{0.0, 100.0, 80.0}};
  const Stock s = make(p);
  EXPECT_DOUBLE_EQ(s.depth_mm(0, 10.0, kPi / 2), 1.5);
  EXPECT_EQ(s.depth_mm(0, 10.0, 1.5 * kPi), 0.0);  // 0.5 − 1 < 0: the tool is in air
}

TEST(Stock, MaxDepthIncludesEccentricityOnTheBlank) {
  EXPECT_NEAR(make(stepped(0.0)).max_depth_mm(), 5.0, 1e-12);
  EXPECT_NEAR(make(stepped(1.0)).max_depth_mm(), 6.0, 1e-12);
  // a later pass deeper than the first, on a turned surface: no eccentricity added
  StockParams p = stepped(1.0);
  p.passes = {{0.0, 300.0, 86.0}, {0.0, 100.0, 70.0}};  // 2 + 1 on the blank, then (86 − 70)/2 = 8
  EXPECT_NEAR(make(p).max_depth_mm(), 8.0, 1e-12);
}

TEST(Stock, VolumeOfACylinderToAnAnnulus) {
  // One pass Ø60 → Ø50 over 120 mm: π/4·(60² − 50²)·120 = 103 672.557 mm³.
  StockParams p;
  p.blank_diameter_mm = {{0.0, 60.0}};
  p.passes = {{10.0, 130.0, 50.0}};
  const double v = kPi / 4.0 * (60.0 * 60.0 - 50.0 * 50.0) * 120.0 / 1000.0;
  EXPECT_NEAR(make(p).volume_to_remove_cm3(), v, 1e-9 * v);
  // two passes to the same final diameter remove the same volume
  p.passes = {{10.0, 130.0, 55.0}, {10.0, 130.0, 50.0}};
  EXPECT_NEAR(make(p).volume_to_remove_cm3(), v, 1e-9 * v);
  // a pass above the surface removes nothing
  p.passes = {{10.0, 130.0, 50.0}, {10.0, 130.0, 55.0}};
  EXPECT_NEAR(make(p).volume_to_remove_cm3(), v, 1e-9 * v);
}

TEST(Stock, VolumeOfTheSteppedShaft) {
  // Pass 0: π/4·[(90² − 80²)·150 + ∫_150^152 (D² − 80²) dz + (84² − 80²)·148], with
  //   D = 90 − 3(z − 150): ∫ D² dz = (90³ − 84³)/9 = 15 144, so the taper adds 15 144 − 2·6400 =
  //   2344.
  // Pass 1: π/4·(80² − 74²)·150;  pass 2: π/4·(74² − 70²)·150.
  const double mm3 = kPi / 4.0 *
                     ((8100.0 - 6400.0) * 150.0 + 2344.0 + (7056.0 - 6400.0) * 148.0 +
                      (6400.0 - 5476.0) * 150.0 + (5476.0 - 4900.0) * 150.0);
  const double cm3 = mm3 / 1000.0;  // 455.088 cm³
  EXPECT_NEAR(make(stepped(0.0)).volume_to_remove_cm3(), cm3, 1e-4 * cm3);
  // eccentricity moves material around the axis, it does not add any (averaged out)
  EXPECT_NEAR(make(stepped(1.0)).volume_to_remove_cm3(), cm3, 1e-4 * cm3);
}

TEST(Stock, ConfigureRejectsBadStock) {
  EXPECT_NO_THROW(make(stepped()));
  auto bad = [](auto mutate) {
    StockParams p = stepped();
    mutate(p);
    Stock s;
    EXPECT_THROW(s.configure(p), std::invalid_argument);
  };
  bad([](StockParams& p) { p.blank_diameter_mm.clear(); });
  bad([](StockParams& p) { p.blank_diameter_mm[1].value = 0.0; });
  bad([](StockParams& p) { p.blank_diameter_mm[2].at_mm = 150.0; });  // not ascending
  bad([](StockParams& p) { p.blank_diameter_mm[2].at_mm = 100.0; });
  bad([](StockParams& p) { p.eccentricity_mm = -0.1; });
  bad([](StockParams& p) { p.passes.clear(); });
  bad([](StockParams& p) { p.passes[1].z_end_mm = p.passes[1].z_start_mm; });
  bad([](StockParams& p) { p.passes[1].z_end_mm = 100.0; });
  bad([](StockParams& p) { p.passes[2].diameter_mm = 0.0; });
  bad([](StockParams& p) { p.passes[0].diameter_mm = -80.0; });
}

}  // namespace
}  // namespace lathectl::cutting
