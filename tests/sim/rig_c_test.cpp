// Rig C (seed 002): the linear tracer simulation against the closed form of the lag, and the
// steady profile error on a cone against the geometry.
//
// Geometry of the profile error. The slide direction is d = (−cos β, sin β). With the tool set to
// cut the template on the first cylinder (the static offset P0/(E0·i) taken up by the setup), the
// tool sits at the template point under the zero-deflection slide position minus q·d, q the lag
// (the "lag_um" channel):  tool = P_T + q·(cos β, −sin β). On a cone y = y_T(x) of slope tan α:
//   δy = y_tool − y_T(x_tool) = −q·sin β − tan α·q·cos β = −q·sin(α + β)/cos α   (equal x)
//   δx = x_tool − x_T(y_tool) = q·cos β + q·sin β/tan α = q·sin(α + β)/sin α      (equal y)
// and on the cone q → v_T/(C0·i), v_T = V_pr·sin α/sin(α + β), so
//   δy_ss = −V_pr·sin α/(C0·i·cos α) = −V_pr·tan α/(C0·i),   δx_ss = V_pr/(C0·i), both independent
// of β (here V_pr = 3 mm/s, C0·i = 60: δx = 50 µm; δy = −13.397, −28.868, −86.603 µm at α = 15, 30,
// 60°).

#include "systems/c_tracer/rig.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace {

using lathectl::systems::c_tracer::Rig;
using lathectl::systems::c_tracer::RigConfig;

constexpr double kDt = 1e-4;
constexpr double kCorner = 0.3e-3;  // cylinder 0 … 0.3 mm, then the cone: t0 = 0.1 s, a step edge
constexpr double kEnd = 1.0e-3;     // template length: 1/3 s of feed at V_pr = 3 mm/s
constexpr double kY0 = 0.020;

RigConfig cone_config(double alpha_deg, double beta_deg) {
  RigConfig c;
  const double al = alpha_deg * std::numbers::pi / 180.0;
  c.profile.add_point(0.0, kY0);
  c.profile.add_point(kCorner, kY0);
  c.profile.add_point(kEnd, kY0 + (kEnd - kCorner) * std::tan(al));
  c.features = {{"line", 0.0, kCorner}, {"cone", kCorner, kEnd}};
  c.beta_rad = beta_deg * std::numbers::pi / 180.0;
  c.feed_m_per_rev = 0.3e-3;
  c.spindle_rpm = 600.0;  // V_pr = 3 mm/s
  c.nonlinear = false;    // linear model, defaults E0 = 2e6 N/m, C0 = 20, M = 100, i = 3, P0 = 500
  return c;
}

struct Angles {
  double alpha_deg, beta_deg;
};

class RigCCone : public ::testing::TestWithParam<Angles> {};

TEST_P(RigCCone, LinearSimulationEqualsClosedForm) {
  const auto [alpha_deg, beta_deg] = GetParam();
  const RigConfig cfg = cone_config(alpha_deg, beta_deg);
  Rig rig;
  rig.configure(cfg, kDt, kDt);
  rig.run();
  ASSERT_TRUE(rig.numerically_sound());
  const auto& rec = rig.recorder();
  ASSERT_GT(rec.rows(), 3000u);
  EXPECT_EQ(rec.dropped(), 0u);
  const double al = alpha_deg * std::numbers::pi / 180.0, be = beta_deg * std::numbers::pi / 180.0;
  const double v_pr = rig.carriage_speed();
  EXPECT_NEAR(v_pr, 3e-3, 1e-15);
  const double v = v_pr * std::sin(al) / std::sin(al + be);
  const auto& lin = cfg.linear;
  const double q_ss = v / (lin.C0_per_s * lin.lever_ratio);
  const double t0 = kCorner / v_pr;  // the stylus reaches the corner (s_T = 0 on the cylinder)
  const auto time = rec.column("time_s");
  const auto lag = rec.column("lag_um");
  double worst = 0.0, worst_t = 0.0;
  for (std::size_t k = 0; k < rec.rows(); ++k) {
    const double tau = time[k] - t0;
    const double want = tau > 0.0 ? lin.lag(0.0, v, v, tau) : 0.0;
    const double err = std::abs(lag[k] * 1e-6 - want);
    if (err > worst) {
      worst = err;
      worst_t = time[k];
    }
  }
  EXPECT_LT(worst, 1e-6 * q_ss) << "α = " << alpha_deg << "°, β = " << beta_deg
                                << "°: worst |sim − closed form| = " << worst * 1e6
                                << " µm at t = " << worst_t << " s, q_ss = " << q_ss * 1e6 << " µm";
  // Settled at the end: the steady lag v_T/(C0·i).
  EXPECT_NEAR(lag[rec.rows() - 1] * 1e-6, q_ss, 1e-6 * q_ss);
}

TEST_P(RigCCone, SteadyProfileErrorOnTheCone) {
  const auto [alpha_deg, beta_deg] = GetParam();
  const RigConfig cfg = cone_config(alpha_deg, beta_deg);
  Rig rig;
  rig.configure(cfg, kDt, kDt);
  rig.run();
  ASSERT_TRUE(rig.numerically_sound());
  const auto& rec = rig.recorder();
  const double al = alpha_deg * std::numbers::pi / 180.0, be = beta_deg * std::numbers::pi / 180.0;
  const double v = rig.carriage_speed() * std::sin(al) / std::sin(al + be);
  const double q = v / (cfg.linear.C0_per_s * cfg.linear.lever_ratio);
  const double dy_want = -q * std::sin(al + be) / std::cos(al);
  const double dx_want = q * std::sin(al + be) / std::sin(al);
  EXPECT_NEAR(dy_want, -rig.carriage_speed() * std::tan(al) / (cfg.linear.C0_per_s * 3.0), 1e-15);
  const std::size_t last = rec.rows() - 1;
  const double dy = rec.column("dy_um")[last] * 1e-6, dx = rec.column("dx_um")[last] * 1e-6;
  EXPECT_NEAR(dy, dy_want, 0.01 * std::abs(dy_want))
      << "α = " << alpha_deg << "°, β = " << beta_deg << "°";
  EXPECT_NEAR(dx, dx_want, 0.01 * std::abs(dx_want))
      << "α = " << alpha_deg << "°, β = " << beta_deg << "°";
  // The tool is on the cone there, and on the cylinder before the corner it cuts the template.
  EXPECT_GT(rec.column("tool_x_mm")[last] * 1e-3, kCorner);
  EXPECT_NEAR(rec.column("dy_um")[100], 0.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Tracer, RigCCone,
                         ::testing::Values(Angles{15, 45}, Angles{30, 45}, Angles{60, 45},
                                           Angles{15, 60}, Angles{30, 60}, Angles{60, 60}),
                         [](const auto& p) {
                           return "alpha" + std::to_string(static_cast<int>(p.param.alpha_deg)) +
                                  "_beta" + std::to_string(static_cast<int>(p.param.beta_deg));
                         });

}  // namespace
