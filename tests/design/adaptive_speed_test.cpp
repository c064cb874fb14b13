// Design formulas of seed 004 and the handbook tool-life law
// (include/lathectl/design/adaptive_speed.hpp), against examples worked by hand.
//
// Seed 004 (USSR author's certificate "Adaptive control system of a lathe"):
//   V_opt = V_p·(S_p/S)^y_v
//   V_p = 150 m/min, S_p = 0.3 mm/rev, y_v = 0.35, S = 0.15 mm/rev:
//   (0.3/0.15)^0.35 = 2^0.35 = e^(0.35·ln 2) = e^(0.35·0.693147) = e^0.242601 = 1.274561
//   V_opt = 150·1.274561 = 191.184 m/min
// Handbook (Kosilova & Meshcheryakov, "Spravochnik tekhnologa-mashinostroitelya", vol. 2, 1985,
// table 17): steel 45 (σв = 750 MPa), carbide T15K6, longitudinal turning, s ≤ 0.7 mm/rev:
//   Cv = 350, xv = 0.15, yv = 0.35, m = 0.2.  V = Cv/(T^m·t^xv·s^yv), at t = 3 mm, s = 0.5 mm/rev,
//   T = 60 min:
//   60^0.2  = e^(0.2·4.094345)   = e^0.818869  = 2.267933
//   3^0.15  = e^(0.15·1.098612)  = e^0.164792  = 1.179148
//   0.5^0.35 = 1/2^0.35 = 1/1.274561           = 0.784584
//   product = 2.267933·1.179148·0.784584 = 2.098157;  V = 350/2.098157 = 166.813 m/min
// Feed per revolution: s = F/n, F = 150 mm/min at n = 1000 rpm → 0.15 mm/rev.

#include "lathectl/design/adaptive_speed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace lathectl::design {
namespace {

TEST(AdaptiveSpeed, OptimalSpeedClosedForm) {
  EXPECT_NEAR(optimal_speed(150.0, 0.3, 0.35, 0.15), 191.184, 1e-3);
  EXPECT_NEAR(optimal_speed(150.0, 0.3, 0.35, 0.3), 150.0, 1e-12);  // at the computed feed
  // Feed up to 0.6 → speed down: 150·0.5^0.35 = 150·0.784584 = 117.688 m/min
  EXPECT_NEAR(optimal_speed(150.0, 0.3, 0.35, 0.6), 117.688, 1e-3);
  EXPECT_NEAR(optimal_speed(150.0, 0.3, 0.0, 0.6), 150.0, 1e-12);  // y_v = 0: speed independent
}

TEST(AdaptiveSpeed, HandbookSpeedForLifeSteel45) {
  EXPECT_NEAR(speed_for_life(350.0, 0.2, 0.15, 0.35, 60.0, 3.0, 0.5), 166.813, 1e-3);
}

TEST(AdaptiveSpeed, ToolLifeRoundTrip) {
  const double v = speed_for_life(350.0, 0.2, 0.15, 0.35, 60.0, 3.0, 0.5);
  EXPECT_NEAR(tool_life_min(350.0, 0.2, 0.15, 0.35, v, 3.0, 0.5), 60.0, 1e-9);
  // Other range of the same table (s ≤ 0.3: Cv = 420, yv = 0.20) at t = 2, s = 0.25, V = 150:
  // T = (420/(150·2^0.15·0.25^0.2))^5 = (420/(150·1.109569·0.757858))^5 = 3.329780^5 = 409.33 min
  const double t = tool_life_min(420.0, 0.2, 0.15, 0.20, 150.0, 2.0, 0.25);
  EXPECT_NEAR(t, 409.334, 1e-3);
  EXPECT_NEAR(speed_for_life(420.0, 0.2, 0.15, 0.20, t, 2.0, 0.25), 150.0, 1e-9);
  // Taylor: halving T raises V by 2^m = 2^0.2 = 1.148698
  EXPECT_NEAR(speed_for_life(350.0, 0.2, 0.15, 0.35, 30.0, 3.0, 0.5) / v, 1.148698, 1e-6);
}

TEST(AdaptiveSpeed, OptimalSpeedKeepsToolLifeAtPlan) {
  // Seed 004's criterion: V_opt follows the feed so that tool life stays at its planned value.
  // With V·s^yv constant, T(V_opt, S) = T(V_p, S_p) (= 249.51 min at t = 3 for these numbers).
  const double t_plan = tool_life_min(350.0, 0.2, 0.15, 0.35, 150.0, 3.0, 0.3);
  for (double s : {0.1, 0.2, 0.45, 0.7}) {
    const double v = optimal_speed(150.0, 0.3, 0.35, s);
    EXPECT_NEAR(tool_life_min(350.0, 0.2, 0.15, 0.35, v, 3.0, s), t_plan, 1e-9 * t_plan) << s;
  }
  EXPECT_NEAR(t_plan, 249.506, 1e-3);
}

TEST(AdaptiveSpeed, FeedPerRevolution) {
  EXPECT_NEAR(feed_per_rev(150.0, 1000.0), 0.15, 1e-15);
  EXPECT_NEAR(feed_per_rev(96.0, 320.0), 0.3, 1e-15);
}

TEST(AdaptiveSpeed, RejectsBadInputsNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message([] { optimal_speed(0.0, 0.3, 0.35, 0.15); }).find("V_p"), std::string::npos);
  EXPECT_NE(message([] { optimal_speed(150, 0.3, 0.35, -0.1); }).find("current feed"),
            std::string::npos);
  EXPECT_NE(message([] { optimal_speed(150, 0.3, -0.35, 0.1); }).find("y_v"), std::string::npos);
  EXPECT_NE(message([&] { tool_life_min(350, 0.2, 0.15, 0.35, nan, 3, 0.5); }).find("speed V"),
            std::string::npos);
  EXPECT_NE(message([] { tool_life_min(350, 0.0, 0.15, 0.35, 100, 3, 0.5); }).find("m must"),
            std::string::npos);
  EXPECT_NE(message([] { speed_for_life(350, 0.2, 0.15, 0.35, 60, 0, 0.5); }).find("depth"),
            std::string::npos);
  EXPECT_NE(message([] { speed_for_life(-1, 0.2, 0.15, 0.35, 60, 3, 0.5); }).find("Cv"),
            std::string::npos);
  EXPECT_NE(message([] { speed_for_life(350, 0.2, 0.15, 0.35, 0, 3, 0.5); }).find("tool life"),
            std::string::npos);
  EXPECT_NE(message([] { feed_per_rev(150, 0); }).find("spindle speed"), std::string::npos);
  EXPECT_NE(message([] { feed_per_rev(0, 1000); }).find("feed rate"), std::string::npos);
  EXPECT_NE(message([] {
              tool_life_min(350, 0.2, 0.15, 0.35, std::numeric_limits<double>::infinity(), 3, 0.5);
            }).find("speed V"),
            std::string::npos);
}

// The planned mode (V_p, S_p) of steel 45 at t_p = 3 mm, T = 60 min, Pz ≤ 2500 N, by hand
// (tables as above; Pz: Cp = 300, x = 1, y = 0.75, n = −0.15, Kp = 1). In the range s ≤ 0.7:
//   V(s) = 350/(60^0.2·3^0.15)·s^−0.35 = 350/(2.267933·1.179148)·s^−0.35 = 130.8789·s^−0.35
//   Pz(s) = 3000·3·s^0.75·V(s)^−0.15 = 9000·130.8789^−0.15·s^(0.75 + 0.0525) = 4332.24·s^0.8025
//   (130.8789^−0.15 = e^(−0.15·4.874272) = e^−0.731141 = 0.481360; 9000·0.481360 = 4332.24)
//   Pz = 2500 → s = (2500/4332.24)^(1/0.8025) = e^(ln 0.577069/0.8025) = e^(−0.549793/0.8025)
//   = e^−0.685100 = 0.504040 mm/rev;  V_p = 130.8789·0.504040^−0.35 = 130.8789·1.270976 = 166.344
PlannedModeInput steel45_plan() {
  PlannedModeInput in;
  in.life = {{{0.3, 420.0, 0.2, 0.15, 0.20}, {0.7, 350.0, 0.2, 0.15, 0.35},
              {1e9, 340.0, 0.2, 0.15, 0.45}}};
  in.ranges = 3;
  in.Cp = 300.0;
  in.x = 1.0;
  in.y = 0.75;
  in.n = -0.15;
  in.depth_mm = 3.0;
  in.life_min = 60.0;
  in.force_limit_N = 2500.0;
  return in;
}

TEST(DesignPlannedMode, ForceLimitSetsTheFeedAndTheLifeSetsTheSpeed) {
  const auto pm = planned_mode(steel45_plan());
  EXPECT_EQ(pm.limit, PlanLimit::Force);
  EXPECT_NEAR(pm.feed_mm_per_rev, 0.504040, 2e-6);
  EXPECT_NEAR(pm.speed_m_per_min, 166.344, 2e-3);
  EXPECT_NEAR(pm.force_N, 2500.0, 1e-6);
  // The speed gives the planned life at S_p (the handbook law, range s ≤ 0.7).
  EXPECT_NEAR(tool_life_min(350.0, 0.2, 0.15, 0.35, pm.speed_m_per_min, 3.0, pm.feed_mm_per_rev),
              60.0, 1e-9);
  EXPECT_NEAR(pm.power_kW, 2500.0 * pm.speed_m_per_min / 60000.0, 1e-12);
  EXPECT_NEAR(pm.mrr_cm3_per_min, 3.0 * pm.feed_mm_per_rev * pm.speed_m_per_min, 1e-9);
}

TEST(DesignPlannedMode, OtherLimitsAndTheFeedRange) {
  auto in = steel45_plan();
  in.force_limit_N = 1e9;  // no force limit: the largest feed, at its range's speed
  auto pm = planned_mode(in);
  EXPECT_EQ(pm.limit, PlanLimit::FeedMax);
  EXPECT_DOUBLE_EQ(pm.feed_mm_per_rev, 0.8);
  EXPECT_NEAR(pm.speed_m_per_min, speed_for_life(340.0, 0.2, 0.15, 0.45, 60.0, 3.0, 0.8), 1e-9);
  in.Rz_limit_um = 20.0;  // Rz = s²/(8r), r = 0.8: s = √(20e−3·6.4) = 0.357771
  pm = planned_mode(in);
  EXPECT_EQ(pm.limit, PlanLimit::Roughness);
  EXPECT_NEAR(pm.feed_mm_per_rev, std::sqrt(20e-3 * 6.4), 1e-9);
  in.Rz_limit_um = 1e9;
  in.power_limit_kW = 5.0;
  pm = planned_mode(in);
  EXPECT_EQ(pm.limit, PlanLimit::Power);
  EXPECT_NEAR(pm.power_kW, 5.0, 1e-9);
  in.power_limit_kW = 0.01;  // not even the smallest feed
  EXPECT_THROW((void)planned_mode(in), std::invalid_argument);
  in = steel45_plan();
  in.ranges = 0;
  EXPECT_THROW((void)planned_mode(in), std::invalid_argument);
}

}  // namespace
}  // namespace lathectl::design
