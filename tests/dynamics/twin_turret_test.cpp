// dynamics::TwinTurretCut's two options beyond the seed against closed forms:
//   - depth division, inter-tool delay from the axial positions: with constant feeds the band of
//     tool 1's passes that bounds tool 2's chip averages to a delay of exactly lag/s revolutions
//     (the mean of ⌊x⌋ over a unit interval [a, a+1] is a); the frozen model reads round(lag/s)
//     + ½ whatever the lag;
//   - process damping (flank indentation): for a vibration whose surface slope stays below the
//     clearance and whose wavelength is long against the wear land VB, the indented area is
//     ½·VB²·ṗ/V while the tool moves into the part (ṗ > 0) and 0 otherwise, whose work per cycle
//     equals a viscous damper of K_sp·w·VB²/(4V) (Chiou & Liang, IJMTM 38 (1998)): a free decay
//     gains Δζ = c_eq/(2·m·ω).
#include "support/library.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/twin_turret.hpp"

namespace lathectl::dynamics {
namespace {

using lathectl::test::library;
constexpr double kPi = std::numbers::pi;

TwinTurretCut::Params depth_division(double lag_mm, InterToolDelay delay) {
  TwinTurretCut::Params p;
  // A stubby part: y stays far below a micrometre, the surfaces stay flat.
  p.part.length_m = 0.3;
  p.part.diameter_m = 0.2;
  p.part.damping_ratio = 0.05;
  p.modes = 1;
  p.cutting.material = *library().find("steel_40Kh");
  p.cutting.approach_angle_deg = 90.0;
  p.setup = TwinSetup::DepthDivision;
  p.depth_mm[0] = p.depth_mm[1] = 0.5;
  p.tool2_lag_mm = lag_mm;
  p.z_start_mm = 100.0;
  p.rpm_nominal = 820.0;
  p.feed_mm_per_rev = 0.12;
  p.inter_tool_delay = delay;
  p.initial_disturbance_um = 0.0;
  return p;
}

// Both tools at the feed, tool 2 `lag` behind, until tool 2 has cut `revs` revolutions.
double delay_after(const TwinTurretCut::Params& p, double revs) {
  TwinTurretCut cut;
  const double dt = 2e-5, w = p.rpm_nominal / 60.0 * 2.0 * kPi;
  cut.configure(p, dt);
  double theta = 0.0;
  const double z0 = p.z_start_mm - 0.5;
  const double total = (p.tool2_lag_mm + 0.5) / p.feed_mm_per_rev + revs;
  while (theta < total * 2.0 * kPi) {
    theta += w * dt;
    const double z1 = z0 + p.feed_mm_per_rev * theta / (2.0 * kPi);
    const double z[2] = {z1, z1 - p.tool2_lag_mm};
    cut.step(theta, p.rpm_nominal, z);
  }
  EXPECT_TRUE(cut.cutting(1));
  EXPECT_NEAR(cut.depth_mm(1), 0.5, 1e-3);  // flat surfaces: tool 2 takes its own layer
  EXPECT_NEAR(cut.chip_mm(1), p.feed_mm_per_rev, 2e-5);  // z read between cells
  EXPECT_EQ(cut.uncut_reads(), 0);
  EXPECT_EQ(cut.clipped_reads(), 0);
  return cut.inter_tool_delay_rev();
}

TEST(TwinTurretCut, DelayFromAxialPositionsIsTheLagInRevolutions) {
  for (double lag : {2.0, 2.06, 1.5}) {
    const double d = delay_after(depth_division(lag, InterToolDelay::AxialPositions), 5.0);
    EXPECT_NEAR(d, lag / 0.12, 0.01) << lag;
  }
}

TEST(TwinTurretCut, FrozenDelayIgnoresTheActualLag) {
  // 2.0 mm and 2.06 mm are 16.67 and 17.17 feeds: both round to 17, read 17.5 revolutions back.
  for (double lag : {2.0, 2.06}) {
    TwinTurretCut cut;
    cut.configure(depth_division(lag, InterToolDelay::Fixed), 2e-5);
    EXPECT_EQ(cut.inter_tool_delay_rev(), 0.0);  // the frozen model does not search
  }
}

// One tool, no regeneration (μ = 0), a tiny chip (static deflection ≈ 1 µm), started from a
// part displacement of `a_um`, with or without the flank's ploughing.
TwinTurretCut::Params single_tool(bool ploughing, double a_um) {
  TwinTurretCut::Params p;
  p.part.length_m = 0.6;
  p.part.diameter_m = 0.04;
  p.part.damping_ratio = 0.012;
  p.modes = 1;
  p.modes_follow_tool = false;
  p.cutting.material = *library().find("steel_40Kh");
  p.cutting.approach_angle_deg = 90.0;
  p.setup = TwinSetup::Single;
  p.depth_mm[0] = 2.0;
  p.overlap = 0.0;
  p.z_start_mm = 300.0;
  p.rpm_nominal = 820.0;
  p.feed_mm_per_rev = 1e-4;
  p.initial_disturbance_um = a_um;
  p.process_damping.enabled = ploughing;
  p.process_damping.wear_land_mm = 0.1;
  p.process_damping.clearance_deg = 6.0;
  return p;
}

// Free decay of one tool's cut with no regeneration (μ = 0) and a tiny chip (the static
// deflection ≈ 1 µm): ζ from the decrement of the half peak-to-trough amplitudes (blind to the
// slow drift of the static point while the first chip builds up), and the frequency.
struct Decay {
  double zeta, f_Hz;
};
Decay free_decay(bool ploughing, double disturbance_um = 5.0, double t_from = 0.08,
                 std::size_t n = 24) {
  const TwinTurretCut::Params p = single_tool(ploughing, disturbance_um);
  TwinTurretCut cut;
  const double dt = 2e-5, w = 820.0 / 60.0 * 2.0 * kPi;
  cut.configure(p, dt);
  std::vector<double> ext, t_ext;  // alternating extrema of y
  double theta = 0.0, y1 = cut.y_m(), y2 = y1;
  for (double t = dt; t < 0.3; t += dt) {
    theta += w * dt;
    const double z[2] = {p.z_start_mm + 1e-6 + p.feed_mm_per_rev * theta / (2.0 * kPi), 0.0};
    cut.step(theta, 820.0, z);
    const double y = cut.y_m();
    if ((y1 - y2) * (y - y1) < 0.0) {
      ext.push_back(y1);
      t_ext.push_back(t - dt);
    }
    y2 = y1;
    y1 = y;
  }
  // Amplitudes from t_from over n/2 cycles.
  std::size_t i0 = 0;
  while (i0 < t_ext.size() && t_ext[i0] < t_from) ++i0;
  EXPECT_LT(i0 + n + 1, ext.size());
  const double a0 = std::abs(ext[i0 + 1] - ext[i0]) / 2.0;
  const double a1 = std::abs(ext[i0 + n + 1] - ext[i0 + n]) / 2.0;
  const double cycles = 0.5 * static_cast<double>(n);
  const double delta = std::log(a0 / a1) / cycles;
  return {delta / std::sqrt(4.0 * kPi * kPi + delta * delta),
          cycles / (t_ext[i0 + n] - t_ext[i0])};
}

TEST(TwinTurretCut, PloughingOfTheWearLandAddsChiouLiangDamping) {
  // 5 µm: the surface slope stays ≤ 0.02 ≪ tan 6°, the wear land alone ploughs.
  const Decay off = free_decay(false), on = free_decay(true);
  EXPECT_NEAR(off.zeta, 0.012, 0.0005);  // the part's own damping
  const BeamModeAt m = beam_mode_at(BeamPart{.length_m = 0.6, .diameter_m = 0.04,
                                             .damping_ratio = 0.012},
                                    0.3, 1);
  const double v = kPi * 0.04 * 820.0 / 60.0;
  const double c_eq = 4e13 * 2e-3 * 1e-4 * 1e-4 / (4.0 * v);  // K_sp·w·VB²/(4V)
  const double dzeta = c_eq / (2.0 * m.mass_kg * 2.0 * kPi * on.f_Hz);
  EXPECT_NEAR((on.zeta - off.zeta) / dzeta, 1.0, 0.08) << on.zeta << " " << off.zeta;
}

// The same cut from a disturbance of `a_um`: half the swing of y over the 11th cycle after the
// start, relative to a_um.
double relative_amplitude_after_10_cycles(bool ploughing, double a_um) {
  const TwinTurretCut::Params p = single_tool(ploughing, a_um);
  TwinTurretCut cut;
  const double dt = 2e-5, w = 820.0 / 60.0 * 2.0 * kPi;
  cut.configure(p, dt);
  double theta = 0.0, lo = 1e9, hi = -1e9;
  for (int i = 1; i <= 2420; ++i) {  // 10.5 … 11 cycles of 226 Hz: i > 2200
    theta += w * dt;
    const double z[2] = {p.z_start_mm + 1e-6 + p.feed_mm_per_rev * theta / (2.0 * kPi), 0.0};
    cut.step(theta, 820.0, z);
    if (i > 2200) lo = std::min(lo, cut.y_m()), hi = std::max(hi, cut.y_m());
  }
  return 0.5 * (hi - lo) * 1e6 / a_um;
}

TEST(TwinTurretCut, PloughingGrowsFasterThanViscousOnceTheSlopePassesTheClearance) {
  // A 150 µm vibration at 226 Hz has a surface slope ṗ/V ≈ 0.12 > tan 6°: the clearance face
  // ploughs too, so it decays much faster than a 5 µm one (the amplitude-limiting
  // nonlinearity). Without ploughing the decay does not depend on the amplitude (linear).
  const double small_off = relative_amplitude_after_10_cycles(false, 5.0);
  const double large_off = relative_amplitude_after_10_cycles(false, 150.0);
  EXPECT_NEAR(large_off / small_off, 1.0, 0.05);
  const double small_on = relative_amplitude_after_10_cycles(true, 5.0);
  const double large_on = relative_amplitude_after_10_cycles(true, 150.0);
  EXPECT_LT(large_on, 0.6 * small_on) << large_on << " " << small_on;
  // And the small one decays as the linear equivalent predicts, e^(−2π(ζ + Δζ)·10.5) within
  // the swing's measure: ζ + Δζ ≈ 0.0258 (above) → 0.18.
  EXPECT_NEAR(small_on, std::exp(-2.0 * kPi * 0.0258 * 10.5), 0.03);
}

}  // namespace
}  // namespace lathectl::dynamics

// The power chip law (issue 48): F(t) = F_linear(t0)·(t/t0)^(1−m), m Kienzle's of each force.
// One tool, no regeneration (μ = 0), the part displaced 50 µm into the tool: the first step's
// depth is t0 + 0.05 mm and its forces are the linear law's times (t/t0)^(−m) (steel_40Kh: m_Fc,
// m_Fp from data/materials.toml). At t = t0 (no displacement) the two laws are the same force.
TEST(TwinTurretCut, PowerChipLawIsKienzlesExponentOnTheDepth) {
  for (const double a_um : {0.0, 50.0, -50.0}) {
    TwinTurretCut lin, pow_law;
    TwinTurretCut::Params p = single_tool(false, a_um);
    lin.configure(p, 2e-5);
    p.chip_law = ChipLaw::Power;
    pow_law.configure(p, 2e-5);
    const double z[2] = {p.z_start_mm + 1e-3, 0.0};
    lin.step(1e-3, 820.0, z);
    pow_law.step(1e-3, 820.0, z);
    const double t = lin.depth_mm(0), r = t / p.depth_mm[0];
    ASSERT_TRUE(lin.cutting(0) && pow_law.cutting(0));
    ASSERT_GT(lin.radial_N(0), 0.0);
    EXPECT_NEAR(t, 2.0 + a_um * 1e-3, 1e-9);
    const auto& mat = p.cutting.material;
    EXPECT_NEAR(pow_law.radial_N(0), lin.radial_N(0) * std::pow(r, -mat.Fp.m),
                1e-12 * lin.radial_N(0));
    EXPECT_NEAR(pow_law.tangential_N(0), lin.tangential_N(0) * std::pow(r, -mat.Fc.m),
                1e-12 * lin.tangential_N(0));
    if (a_um == 0.0) {
      EXPECT_DOUBLE_EQ(pow_law.radial_N(0), lin.radial_N(0));
    }
  }
}
