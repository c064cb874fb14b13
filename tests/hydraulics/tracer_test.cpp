// Linearised hydraulic tracer slide (seed 002, (8)-(9)): closed forms of ζ and ω_n, the lag's
// closed form against its ODE, the transient scan, the template polyline and the slide target.
//   (M/E0)·q̈ + q̇/C0 + i·q = v/C0,   ω_n² = i·E0/M,   ζ = sqrt(E0/(M·i))/(2·C0)

#include "lathectl/hydraulics/tracer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace {

using lathectl::hydraulics::slide_target;
using lathectl::hydraulics::TemplateProfile;
using lathectl::hydraulics::TracerLinear;

TracerLinear with_c0(double c0) {
  TracerLinear t;  // E0 = 2e6 N/m, M = 100 kg, i = 3, P0 = 500 N
  t.C0_per_s = c0;
  return t;
}
// ζ = 1 exactly: C0 = sqrt(E0/(M·i))/2.
TracerLinear critical() {
  return with_c0(std::sqrt(2e6 / (100.0 * 3.0)) / 2.0);
}

constexpr double kV = 1.5e-3;  // template rate along the slide [m/s]

TEST(TracerLinear, ZetaAndOmegaClosedForms) {
  const TracerLinear t;  // E0 = 2e6, C0 = 20, M = 100, i = 3
  EXPECT_NEAR(t.omega_n(), std::sqrt(3.0 * 2e6 / 100.0), 1e-12);  // 244.94897 rad/s
  EXPECT_NEAR(t.zeta(), std::sqrt(2e6 / 300.0) / 40.0, 1e-15);    // 2.041241
  EXPECT_NEAR(t.zeta(), 2.0412414523, 1e-9);
  EXPECT_TRUE(t.aperiodic());
  // The characteristic polynomial (M/E0)λ² + λ/C0 + i has 2ζω_n = E0/(M·C0).
  EXPECT_NEAR(2.0 * t.zeta() * t.omega_n(), 2e6 / (100.0 * 20.0), 1e-9);
  EXPECT_FALSE(with_c0(60.0).aperiodic());
  EXPECT_NEAR(with_c0(60.0).zeta(), t.zeta() / 3.0, 1e-15);
  EXPECT_NEAR(critical().zeta(), 1.0, 1e-15);
  EXPECT_TRUE(critical().aperiodic());
  EXPECT_NEAR(t.static_offset_m(), 500.0 / (2e6 * 3.0), 1e-18);
  EXPECT_NEAR(t.steady_lag_m(kV), (500.0 / 2e6 + kV / 20.0) / 3.0, 1e-18);
}

struct Case {
  const char* name;
  double c0;  // 60 → ζ = 0.68, 0 → ζ = 1 exactly, 20 → ζ = 2.04
  double q0, qd0, v;
};

TracerLinear system_of(const Case& c) {
  return c.c0 > 0.0 ? with_c0(c.c0) : critical();
}

class LagOde : public ::testing::TestWithParam<Case> {};

TEST_P(LagOde, SatisfiesOdeAndInitialConditions) {
  const Case c = GetParam();
  const TracerLinear t = system_of(c);
  const double a = t.mass_kg / t.E0_N_per_m, b = 1.0 / t.C0_per_s, k = t.lever_ratio;
  auto q = [&](double tau) { return t.lag(c.q0, c.qd0, c.v, tau); };
  const double h = 1e-3 / t.omega_n();
  // Initial conditions (the closed form is analytic, so q(−h) is fine for a central difference).
  EXPECT_DOUBLE_EQ(q(0.0), c.q0) << c.name;
  const double qd_0 = (q(h) - q(-h)) / (2.0 * h);
  EXPECT_NEAR(qd_0, c.qd0, 1e-6 * (std::abs(c.qd0) + std::abs(c.v) + t.omega_n() * std::abs(c.q0)))
      << c.name;
  for (double tau_wn : {0.05, 0.3, 1.0, 2.5, 6.0, 15.0}) {
    const double tau = tau_wn / t.omega_n();
    const double q0 = q(tau), qp = q(tau + h), qm = q(tau - h);
    const double qd = (qp - qm) / (2.0 * h), qdd = (qp - 2.0 * q0 + qm) / (h * h);
    const double res = a * qdd + b * qd + k * q0 - b * c.v;
    const double scale =
        std::abs(a * qdd) + std::abs(b * qd) + std::abs(k * q0) + std::abs(b * c.v);
    EXPECT_LT(std::abs(res), 1e-6 * scale) << c.name << " at ω_n·τ = " << tau_wn;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Tracer, LagOde,
    ::testing::Values(Case{"underdamped_cyl_to_cone", 60.0, 0.0, kV, kV},
                      Case{"critical_cyl_to_cone", 0.0, 0.0, kV, kV},
                      Case{"overdamped_cyl_to_cone", 20.0, 0.0, kV, kV},
                      Case{"underdamped_cone_to_cyl", 60.0, kV / (60.0 * 3.0), -kV, 0.0},
                      Case{"critical_step", 0.0, 50e-6, 0.0, 0.0},
                      Case{"overdamped_cone_to_cyl", 20.0, kV / (20.0 * 3.0), -kV, 0.0}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(TracerLinear, CriticalBranchIsContinuousWithItsNeighbours) {
  // ζ = 1 takes the (A + Bτ)e^{λτ} branch; ζ = 1 ± 1e-6 the two-root one: they must agree.
  const TracerLinear c = critical();
  for (double f : {1.0 - 1e-6, 1.0 + 1e-6}) {
    const TracerLinear n = with_c0(c.C0_per_s / f);
    for (double tau : {1e-3, 5e-3, 2e-2, 6e-2}) {
      const double qc = c.lag(0.0, kV, kV, tau), qn = n.lag(0.0, kV, kV, tau);
      EXPECT_NEAR(qn, qc, 1e-5 * c.steady_lag_m(kV)) << "ζ = " << f << ", τ = " << tau;
    }
  }
}

TEST(TracerLinear, LagTendsToSteadyValueOnCone) {
  for (double c0 : {60.0, 0.0, 20.0}) {
    const TracerLinear t = c0 > 0.0 ? with_c0(c0) : critical();
    const double q_ss = kV / (t.C0_per_s * t.lever_ratio);
    EXPECT_NEAR(t.lag(0.0, kV, kV, 5.0), q_ss, 1e-12 * q_ss) << "C0 = " << t.C0_per_s;
    // steady_lag_m adds the static part P0/(E0·i).
    EXPECT_NEAR(t.steady_lag_m(kV) - t.static_offset_m(), q_ss, 1e-12 * q_ss);
  }
}

TEST(TracerLinear, ConeToCylinderReturnsToZero) {
  for (double c0 : {60.0, 0.0, 20.0}) {
    const TracerLinear t = c0 > 0.0 ? with_c0(c0) : critical();
    const double q_ss = kV / (t.C0_per_s * t.lever_ratio);
    EXPECT_NEAR(t.lag(q_ss, -kV, 0.0, 0.0), q_ss, 1e-15);
    EXPECT_NEAR(t.lag(q_ss, -kV, 0.0, 5.0), 0.0, 1e-12 * q_ss) << "C0 = " << t.C0_per_s;
    // Superposition: cone→cylinder = steady cone lag minus a fresh cylinder→cone response.
    for (double tau : {2e-3, 1e-2, 4e-2})
      EXPECT_NEAR(t.lag(q_ss, -kV, 0.0, tau), q_ss - t.lag(0.0, kV, kV, tau), 1e-12 * q_ss);
  }
}

TEST(TracerLinear, AperiodicTransientHasNoOvershoot) {
  for (double c0 : {0.0, 20.0, 10.0}) {
    const TracerLinear t = c0 > 0.0 ? with_c0(c0) : critical();
    ASSERT_TRUE(t.aperiodic());
    const double q_ss = kV / (t.C0_per_s * t.lever_ratio);
    const auto tr = t.transient(0.0, kV, kV);
    EXPECT_NEAR(tr.peak_m, q_ss, 1e-9 * q_ss) << "C0 = " << t.C0_per_s;
    EXPECT_GT(tr.settling_s, 0.0);
  }
  // ζ = 2.04: slow root λ1 = −ω_n(ζ − sqrt(ζ² − 1)); the 2 % band is reached when
  // |c1|·e^{λ1·τ} = 0.02·q_ss, c1 = (v + λ2·q_ss)/(λ1 − λ2) (the fast term is negligible then).
  const TracerLinear t;
  const double wn = t.omega_n(), z = t.zeta(), q_ss = kV / (t.C0_per_s * t.lever_ratio);
  const double l1 = -wn * (z - std::sqrt(z * z - 1.0)), l2 = -wn * (z + std::sqrt(z * z - 1.0));
  const double c1 = (kV + l2 * q_ss) / (l1 - l2);
  const double tau_s = std::log(std::abs(c1) / (0.02 * q_ss)) / -l1;
  EXPECT_NEAR(t.transient(0.0, kV, kV).settling_s, tau_s, 1e-3 * tau_s);
}

TEST(TracerLinear, UnderdampedTransientOvershootsLikeTheRampResponse) {
  const TracerLinear t = with_c0(60.0);  // ζ = 0.680414
  const double wn = t.omega_n(), z = t.zeta(), wd = wn * std::sqrt(1.0 - z * z);
  const double q_ss = kV / (t.C0_per_s * t.lever_ratio);
  // Independent form: q = q_ss + e^{−ζω_nτ}(A cos ω_dτ + B sin ω_dτ), q(0) = 0, q̇(0) = v.
  const double A = -q_ss, B = (kV + z * wn * A) / wd;
  auto q = [&](double tau) {
    return q_ss + std::exp(-z * wn * tau) * (A * std::cos(wd * tau) + B * std::sin(wd * tau));
  };
  double peak = 0.0;
  const double horizon = 40.0 / wn;
  for (int k = 0; k <= 400000; ++k) peak = std::max(peak, std::abs(q(horizon * k / 400000.0)));
  // Textbook: q̇ obeys the homogeneous equation with q̇(0) = v, q̈(0) = 0, so its first zero is
  // at ω_d·τ_p = π − arccos ζ.
  const double tau_p = (std::numbers::pi - std::acos(z)) / wd;
  EXPECT_NEAR(peak, q(tau_p), 1e-9 * q_ss);
  EXPECT_GT(peak, 1.05 * q_ss);  // ≈ 7.8 % overshoot at ζ = 0.68
  const auto tr = t.transient(0.0, kV, kV);
  EXPECT_NEAR(tr.peak_m, peak, 1e-5 * q_ss);
  EXPECT_GT(tr.peak_m, q_ss);
  EXPECT_NEAR(t.lag(0.0, kV, kV, tau_p), q(tau_p), 1e-12 * q_ss);
}

TEST(TemplateProfile, InterpolatesAndHandlesVerticalSteps) {
  TemplateProfile tp;
  EXPECT_TRUE(tp.empty());
  EXPECT_EQ(tp.y_at(1.0), 0.0);
  tp.add_point(0.0, 0.0);
  tp.add_point(1.0, 0.0);
  tp.add_point(2.0, 1.0);
  tp.add_point(2.0, 3.0);  // vertical step up at x = 2
  tp.add_point(3.0, 3.0);
  tp.add_point(4.0, 2.0);
  EXPECT_THROW(tp.add_point(3.5, 0.0), std::invalid_argument);
  EXPECT_EQ(tp.xs().size(), 6u);
  EXPECT_EQ(tp.y_at(-1.0), 0.0);  // before the first point: its height
  EXPECT_EQ(tp.y_at(9.0), 2.0);   // after the last
  EXPECT_DOUBLE_EQ(tp.y_at(0.5), 0.0);
  EXPECT_DOUBLE_EQ(tp.y_at(1.25), 0.25);
  EXPECT_DOUBLE_EQ(tp.y_at(1.5), 0.5);
  EXPECT_NEAR(tp.y_at(2.0 - 1e-12), 1.0, 1e-11);  // just before the step: the lower side
  EXPECT_DOUBLE_EQ(tp.y_at(2.0), 3.0);            // on the step: the later point
  EXPECT_DOUBLE_EQ(tp.y_at(2.0 + 1e-12), 3.0);
  EXPECT_DOUBLE_EQ(tp.y_at(3.5), 2.5);
  EXPECT_DOUBLE_EQ(tp.y_at(4.0), 2.0);
}

TEST(SlideTarget, AdvancesAtTheConeRate) {
  // Cylinder y = 20 mm to x = 1 mm, then a cone of angle α to x = 10 mm.
  for (double alpha_deg : {15.0, 30.0, 60.0}) {
    for (double beta_deg : {45.0, 60.0, 90.0}) {
      const double al = alpha_deg * std::numbers::pi / 180.0,
                   be = beta_deg * std::numbers::pi / 180.0;
      TemplateProfile tp;
      tp.add_point(0.0, 0.020);
      tp.add_point(0.001, 0.020);
      tp.add_point(0.010, 0.020 + 0.009 * std::tan(al));
      EXPECT_NEAR(slide_target(tp, 0.0005, 0.020, be, -0.05, 0.05), 0.0, 1e-15);
      const double xa = 0.002, xb = 0.0035;
      const double sa = slide_target(tp, xa, 0.020, be, -0.05, 0.05);
      const double sb = slide_target(tp, xb, 0.020, be, -0.05, 0.05);
      const double rate = std::sin(al) / std::sin(al + be);  // ds_T/dx_c
      EXPECT_NEAR(sb - sa, rate * (xb - xa), 1e-9 * rate * (xb - xa))
          << alpha_deg << "/" << beta_deg;
      EXPECT_NEAR(sa, rate * (xa - 0.001), 1e-9 * rate * xa);
      // The stylus is on the template there.
      EXPECT_NEAR(0.020 + sb * std::sin(be), tp.y_at(xb - sb * std::cos(be)), 1e-14);
    }
  }
}

}  // namespace

// Seed 002's (12)-(13) on the design calculator's default case (β = 45°, α = 30°, V_pr = 3 mm/s,
// C0·i = 60 1/s), by hand from the geometry in tests/sim/rig_c_test.cpp's header:
//   v_T = 3·sin 30°/sin 75° = 1.552914 mm/s, q = v_T/(C0·i) = 25.881905 µm
//   δx = q·sin 75°/sin 30° = 25.881905·0.9659258/0.5 = 50.000000 µm = V_pr/(C0·i) = 3/60 mm
//   δy = −q·sin 75°/cos 30° = −25.881905·0.9659258/0.8660254 = −28.867513 µm = −V_pr·tan 30°/60
TEST(TracerProfileError, SeedTwelveThirteenByHand) {
  using lathectl::hydraulics::cone_profile_error;
  constexpr double kDeg = std::numbers::pi / 180.0;
  const double q = 3e-3 * std::sin(30.0 * kDeg) / std::sin(75.0 * kDeg) / 60.0;
  EXPECT_NEAR(q, 25.881905e-6, 1e-12);
  const auto e = cone_profile_error(q, 30.0 * kDeg, 45.0 * kDeg);
  EXPECT_NEAR(e.dx_m, 50.000000e-6, 1e-12);
  EXPECT_NEAR(e.dy_m, -28.867513e-6, 1e-12);
  // Free of β at the steady lag: the same δx, δy at β = 60° with its own v_T.
  const double q60 = 3e-3 * std::sin(30.0 * kDeg) / std::sin(90.0 * kDeg) / 60.0;
  const auto e60 = cone_profile_error(q60, 30.0 * kDeg, 60.0 * kDeg);
  EXPECT_NEAR(e60.dx_m, 50e-6, 1e-15);
  EXPECT_NEAR(e60.dy_m, -28.867513e-6, 1e-12);
  // No equal y on a cylinder, no equal x on a shoulder.
  EXPECT_TRUE(std::isnan(cone_profile_error(q, 0.0, 45.0 * kDeg).dx_m));
  EXPECT_TRUE(std::isnan(cone_profile_error(q, 90.0 * kDeg, 45.0 * kDeg).dy_m));
  // Fig. 1's static characteristic (9) at dV/dt = 0: h = P/E0 + V/C0 = 500/2e6 + 1.5e-3/20.
  EXPECT_NEAR(TracerLinear{}.static_opening_m(500.0, 1.5e-3), 0.25e-3 + 0.075e-3, 1e-18);
}
