// The planner's acceleration in the predicted cycle time (predict.cpp, acceleration_time):
// against the trapezoid's closed forms, and where a program's planner stops or runs on.
// The check against LinuxCNC itself is in tests/hal/optimize_verify_test.py (the predicted cycle
// within 0.8 s of the measured one, of which about 0.6 s is LinuxCNC starting the program).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "lathectl/io/canon.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "optimize/optimize.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

// A move from rest to rest at v with acceleration a loses v/a against len/v when it is long
// enough to reach v (len ≥ v²/a); shorter, it is a triangle: 2·√(len/a).
TEST(Accel, LegTimeIsTheTrapezoidOrTheTriangle) {
  EXPECT_NEAR(leg_time(100.0, 80.0, 0.0, 0.0, 500.0), 100.0 / 80.0 + 80.0 / 500.0, 1e-12);
  EXPECT_NEAR(leg_time(5.0, 80.0, 0.0, 0.0, 500.0), 2.0 * std::sqrt(5.0 / 500.0), 1e-12);
  // entered at speed, braked to rest: half the loss
  EXPECT_NEAR(leg_time(100.0, 80.0, 80.0, 0.0, 500.0), 100.0 / 80.0 + 80.0 / 1000.0, 1e-12);
  EXPECT_NEAR(leg_time(100.0, 80.0, 80.0, 80.0, 500.0), 100.0 / 80.0, 1e-12);
}

TEST(Accel, StopsOnlyWhereThePlannerStops) {
  const double v = 80.0, a = 500.0;
  // two legs that run on: one leg of their length
  EXPECT_NEAR(acceleration_time({{50.0, v, a, false}, {50.0, v, a, true}}), v / a, 1e-12);
  // a stop between them: twice
  EXPECT_NEAR(acceleration_time({{50.0, v, a, true}, {50.0, v, a, true}}), 2.0 * v / a, 1e-12);
  // into a slower leg: braking 80 → 40 loses (v1 − v2)²/(2·a·v1), and 40 → 0 at the end 40/(2a)
  EXPECT_NEAR(acceleration_time({{100.0, 80.0, a, false}, {100.0, 40.0, a, true}}),
              80.0 / 1000.0 + 40.0 * 40.0 / (1000.0 * 80.0) + 40.0 / 1000.0, 1e-12);
  // legs too short to reach the speed between two stops: a triangle over the three
  EXPECT_NEAR(acceleration_time({{1.0, v, a, false}, {1.0, v, a, false}, {1.0, v, a, true}}),
              2.0 * std::sqrt(3.0 / a) - 3.0 / v, 1e-12);
  EXPECT_EQ(acceleration_time({}), 0.0);
}

const systems::e_adaptive::Settings& step_allowance() {
  static const auto lib = io::MaterialLibrary::load_default();
  static const auto sc =
      io::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  return sc.get<systems::e_adaptive::Settings>();
}

// A rapid to the start of a G95 pass and the pass: LinuxCNC stops between them (a rapid and a
// feed move are not blended, blend.hpp), and the rapid alone loses v/a; the pass split into
// three pieces of one feed runs on through the splits, as LinuxCNC runs tangent segments.
TEST(Accel, SplitPiecesRunOnAndARapidStopsBeforeTheCut) {
  io::CanonProgram prog;
  CanonMove m;
  m.spindle_on = true;
  m.speed = 1194.0;
  m.per_rev = true;
  m.feed = 0.3;
  m.kind = CanonMove::Kind::Traverse;
  m.x0 = 60.0, m.z0 = 60.0, m.x1 = 18.0, m.z1 = 2.0;
  prog.moves.push_back(m);
  m.kind = CanonMove::Kind::Line;
  m.x0 = 18.0, m.z0 = 2.0, m.x1 = 18.0, m.z1 = -12.0;
  prog.moves.push_back(m);
  const Options opt;
  const auto& e = step_allowance();
  const Plan whole = programmed(prog);
  Plan split = whole;
  split[1] = {{0.0, 0.3, 0.3, "", 0}, {0.3, 0.6, 0.3, "", 0}, {0.6, 1.0, 0.3, "", 0}};
  const double v_rapid = e.rig.rapid_m_per_s * 1000.0, v_feed = 0.3 * 1194.0 / 60.0;
  const double a = opt.machine.accel_mm_s2;
  const double rapid_len = std::hypot(42.0, 58.0);
  ASSERT_GE(rapid_len, v_rapid * v_rapid / a);  // long enough to reach the rapid
  const auto p_whole = predict(prog, whole, e, opt);
  const auto p_split = predict(prog, split, e, opt);
  EXPECT_NEAR(p_whole.accel_time_s, v_rapid / a + v_feed / a, 1e-6);
  EXPECT_NEAR(p_split.accel_time_s, p_whole.accel_time_s, 1e-9);
  EXPECT_NEAR(p_whole.cycle_time_s,
              rapid_len / v_rapid + 14.0 / v_feed + p_whole.accel_time_s, 2e-3);
}

}  // namespace
}  // namespace lathectl::optimize
