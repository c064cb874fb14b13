// lathectl optimize: the canonical-command reader, the program text edits, the
// prediction against the cutting model's closed form, the planner's acceleration against the
// trapezoid's, the feed solver against its inverse, and the rewrite of a real program within the
// limits (that part needs LinuxCNC's rs274).
#include "optimize/optimize.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <tuple>

#include "lathectl/control/per_revolution.hpp"
#include "lathectl/io/canon.hpp"
#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "optimize/path.hpp"
#include "optimize/plan.hpp"
#include "optimize/text.hpp"
#include "systems/registry.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

const systems::e_adaptive::Settings& step_allowance() {
  static const auto lib = io::MaterialLibrary::load_default();
  static const auto sc =
      systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  return sc.get<systems::e_adaptive::Settings>();
}

bool have_rs274() {
  return std::filesystem::exists("/usr/bin/rs274");
}
Options options() {
  Options o;
  o.ini = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  o.rs274 = "/usr/bin/rs274";
  return o;
}

// rs274's output for "G18 G21 G95 / G96 D2000 S150 M3 / G0 X25 Z5 / G1 Z-50 F0.3 /
// G33 Z-60 K1.5 / G2 X12 Z-62 I2 K0" (printed by rs274 -g of linuxcnc-uspace 2.9), markers added.
constexpr const char* kCanon = R"(executing
    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    7 N..... COMMENT("lathectl-line 1")
    8 N..... SET_FEED_MODE(0, 1)
    9 N..... SET_FEED_RATE(0.0000)
   10 N..... SELECT_PLANE(CANON_PLANE_XZ)
   11 N..... COMMENT("lathectl-line 3")
   17 N..... SET_SPINDLE_MODE(0 2000.0000)
   18 N..... SET_SPINDLE_SPEED(0, 150.0000)
   19 N..... START_SPINDLE_CLOCKWISE(0)
   20 N..... COMMENT("lathectl-line 4")
   21 N..... STRAIGHT_TRAVERSE(25.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)
   22 N..... COMMENT("lathectl-line 5")
   23 N..... SET_FEED_RATE(0.3000)
   24 N..... STRAIGHT_FEED(25.0000, 0.0000, -50.0000, 0.0000, 0.0000, 0.0000)
   25 N..... COMMENT("lathectl-line 6")
   30 N..... START_SPEED_FEED_SYNC(1.500000,0)
   31 N..... STRAIGHT_FEED(10.0000, 0.0000, -60.0000, 0.0000, 0.0000, 0.0000)
   32 N..... STOP_SPEED_FEED_SYNCH()
   33 N..... COMMENT("lathectl-line 7")
   34 N..... ARC_FEED(-62.0000, 12.0000, -60.0000, 12.0000, -1, 0.0000, 0.0000, 0.0000, 0.0000)
)";

TEST(Canon, ReadsMovesModesAndLines) {
  const auto p = io::parse_canon(kCanon, "t.ngc", 60.0, 60.0);
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_EQ(p.moves[0].kind, CanonMove::Kind::Traverse);
  EXPECT_EQ(p.moves[0].line, 4);
  EXPECT_DOUBLE_EQ(p.moves[0].x0, 60.0);
  const auto& cut = p.moves[1];
  EXPECT_EQ(cut.line, 5);
  EXPECT_TRUE(cut.per_rev);
  EXPECT_DOUBLE_EQ(cut.feed, 0.3);
  EXPECT_TRUE(cut.css);
  EXPECT_DOUBLE_EQ(cut.css_max_rpm, 2000.0);
  EXPECT_DOUBLE_EQ(cut.speed, 150.0);
  EXPECT_TRUE(cut.spindle_on);
  EXPECT_DOUBLE_EQ(cut.z1, -50.0);
  EXPECT_TRUE(p.moves[2].synced);
  EXPECT_FALSE(p.moves[3].synced);
  const auto& arc = p.moves[3];
  EXPECT_EQ(arc.kind, CanonMove::Kind::Arc);
  EXPECT_EQ(arc.rotation, -1);
  EXPECT_DOUBLE_EQ(arc.x1, 12.0);
  EXPECT_DOUBLE_EQ(arc.z1, -62.0);
  EXPECT_DOUBLE_EQ(arc.xc, 12.0);
  EXPECT_DOUBLE_EQ(arc.zc, -60.0);
  // G96: n = 1000·V/(2π·x) at x = 25 mm, below D = 2000
  EXPECT_NEAR(spindle_rpm(cut, 25.0), 1000.0 * 150.0 / (2.0 * std::numbers::pi * 25.0), 1e-9);
  EXPECT_DOUBLE_EQ(spindle_rpm(cut, 0.5), 2000.0);
}

TEST(Canon, RefusesWhatItCannotRead) {
  EXPECT_THROW(io::parse_canon("1 N..... STRAIGHT_FEED(1.0, 0.0, x, 0, 0, 0)\n", "t"),
               io::InputError);
  EXPECT_THROW(io::parse_canon("1 N..... SELECT_PLANE(CANON_PLANE_XY)\n"
                               "2 N..... ARC_FEED(1, 0, 0, 0, 1, 0, 0, 0, 0)\n",
                               "t"),
               io::InputError);
  EXPECT_NO_THROW(io::parse_canon("garbage\n  \n 12 N5 SOMETHING_NEW(1,2)\n", "t"));
  // make test's fuzz step (run 5 of 10, 2026-11-26): a tool number of 2.9e54 was undefined
  // behaviour in its conversion to int (fuzz/regressions/canon/select_tool_2.9e54.txt).
  EXPECT_THROW(io::parse_canon("1 N..... SELECT_TOOL(2.88889e+54)\n", "t"), io::InputError);
  EXPECT_THROW(io::parse_canon("1 N..... SELECT_TOOL(-1)\n", "t"), io::InputError);
  EXPECT_NO_THROW(io::parse_canon("1 N..... SELECT_TOOL(2)\n", "t"));
}

// T only prepares the next tool; M6 (CHANGE_TOOL, whose argument is the tool table's pocket, not
// the tool number) puts it in the spindle. The moves between cut with the tool still in it, as
// LinuxCNC's iocontrol.0.tool-number (the pin the LinuxCNC plant reads) says.
TEST(Canon, TheToolInTheSpindleChangesAtM6NotAtT) {
  const auto p = io::parse_canon(
      "1 N..... SELECT_TOOL(1)\n"
      "2 N..... CHANGE_TOOL(1)\n"
      "3 N..... SELECT_TOOL(10)\n"
      "4 N..... STRAIGHT_TRAVERSE(5.0, 0.0, 1.0, 0.0, 0.0, 0.0)\n"
      "5 N..... CHANGE_TOOL(3)\n"
      "6 N..... STRAIGHT_TRAVERSE(6.0, 0.0, 1.0, 0.0, 0.0, 0.0)\n",
      "t");
  ASSERT_EQ(p.moves.size(), 2U);
  EXPECT_EQ(p.moves[0].tool, 1);
  EXPECT_EQ(p.moves[1].tool, 10);
}

TEST(Text, FeedWordsAndMarkers) {
  EXPECT_EQ(with_feed("G1 Z-50 F0.3", "0.4500").value(), "G1 Z-50 F0.4500");
  EXPECT_EQ(with_feed("G1 Z-50 f 0.3 (cut)", "0.4500").value(), "G1 Z-50 f 0.4500 (cut)");
  EXPECT_EQ(with_feed("G1 Z-50 ; cut", "0.4500").value(), "G1 Z-50 F0.4500 ; cut");
  EXPECT_EQ(with_feed("G1 Z-50 (F0.2 in a comment)", "0.4").value(),
            "G1 Z-50 (F0.2 in a comment) F0.4");
  EXPECT_FALSE(with_feed("G1 Z-50 F#1", "0.4").has_value());
  EXPECT_FALSE(with_feed("G1 Z-50 F[#1*2]", "0.4").has_value());
  EXPECT_TRUE(keep_marked("G1 Z-5 F0.1 ( Lathectl:Keep )"));
  EXPECT_FALSE(keep_marked("G1 Z-5 F0.1 (keep)"));
  const auto m = marked_lines({"%", "G1 X1 ; c", "o100 sub", "", "%"}, 1200.0);
  ASSERT_EQ(m.size(), 6u);
  EXPECT_EQ(m[0], "%");
  EXPECT_EQ(m[1], "M3 S1200");
  EXPECT_EQ(m[2], "G1 X1  (lathectl-line 2); c");
  EXPECT_EQ(m[3], "o100 sub");
  EXPECT_EQ(m[5], "%");
}

// A straight turning pass, 2 mm deep at 0.3 mm/rev and 1194 rpm on step_allowance.toml's 40 mm
// bar: the prediction's steady chip and force against the handbook's closed form
// Pz = 10·Cp·t^x·s^y·V^n·Kmp (Kosilova & Meshcheryakov vol. 2; cutting_model.hpp), V = π·D·n/1000.
// A rapid from (x0, z0) to X18 Z2 and a G95 pass at X18 to Z-12, 0.3 mm/rev at 1194 rpm (on
// step_allowance.toml's bar: 2 mm deep; the collar begins at 15 mm).
io::CanonProgram rapid_and_pass(double x0, double z0) {
  io::CanonProgram prog;
  CanonMove m;
  m.spindle_on = true;
  m.speed = 1194.0;
  m.per_rev = true;
  m.feed = 0.3;
  m.kind = CanonMove::Kind::Traverse;
  m.x0 = x0, m.z0 = z0, m.x1 = 18.0, m.z1 = 2.0;
  prog.moves.push_back(m);
  m.kind = CanonMove::Kind::Line;
  m.x0 = 18.0, m.z0 = 2.0, m.x1 = 18.0, m.z1 = -12.0;
  prog.moves.push_back(m);
  return prog;
}

TEST(Predict, StraightPassMatchesTheHandbookForce) {
  const auto& e = step_allowance();
  const io::CanonProgram prog = rapid_and_pass(25.0, 5.0);
  const Options opt;
  const auto pr = predict(prog, programmed(prog), e, opt);
  const auto& s = pr.s;
  const double t = 2.0, f = 0.3, v = std::numbers::pi * 40.0 * 1194.0 / 1000.0;
  const auto& mat = e.rig.cutting.material;
  const double kmp = std::pow(mat.strength / mat.strength_base, mat.kmp_exponent);
  const double pz = 10.0 * mat.Pz.Cp * std::pow(t, mat.Pz.x) * std::pow(f, mat.Pz.y) *
                    std::pow(v, mat.Pz.n) * kmp;
  std::size_t at = 0;
  for (std::size_t i = 0; i < s.path_mm.size(); ++i)
    if (s.move[i] == 1 && s.x[i] == 18.0 && s.path_mm[i] >= s.path_mm.back() - 2.0) {
      at = i;
      break;
    }
  ASSERT_GT(at, 0u);
  EXPECT_NEAR(s.depth[at], t, 0.01 * t);
  EXPECT_NEAR(s.feed_rev[at], f, 0.005 * f);
  EXPECT_NEAR(s.speed[at], v, 0.01 * v);
  EXPECT_NEAR(s.pz[at], pz, 0.02 * pz);
  EXPECT_NEAR(s.torque[at], s.pz[at] * 20.0e-3, 0.01 * s.pz[at] * 20.0e-3);
  // time of the feed move: its length over F·n
  double t_feed = 0.0;
  for (std::size_t i = 0; i < s.move.size(); ++i) t_feed += s.move[i] == 1 ? s.dt[i] : 0.0;
  EXPECT_NEAR(t_feed, 14.0 / (f * 1194.0 / 60.0), 1e-9);
}

// A shoulder where the program puts it (issue 47): the pass at X18 to Z-12 then faces the shoulder
// up to X21 at Z-12. The programmed point is the tool tip of its orientation: with the scenario's
// (Q2) the bar stays whole from Z-12 on toward the chuck and the pass's diameter is X18; a tool
// table's Q6 for tool 1 (the nose's lowest point programmed) cuts the face one nose radius
// deeper, at Z-12.8, as the plant did before.
TEST(Predict, AShoulderIsWhereTheToolTipOfItsOrientationPutsIt) {
  const auto& e = step_allowance();
  const double r = e.rig.cutting.nose_radius_mm;
  io::CanonProgram prog = rapid_and_pass(25.0, 5.0);
  CanonMove m = prog.moves.back();
  m.x0 = 18.0, m.z0 = -12.0, m.x1 = 21.0, m.z1 = -12.0;
  prog.moves.push_back(m);
  for (auto& mv : prog.moves) mv.tool = 1;
  auto radius_at = [](const Prediction& pr, double z) {  // the part's profile point nearest z
    std::size_t k = 0;
    for (std::size_t i = 0; i < pr.part_z.size(); ++i)
      if (std::abs(pr.part_z[i] - z) < std::abs(pr.part_z[k] - z)) k = i;
    return pr.part_r[k];
  };
  Options opt;
  opt.blends = false;  // the programmed corner, not G64's blend arc across it
  const auto tip = predict(prog, programmed(prog), e, opt);
  const double rz = 0.3 * 0.3 / (8.0 * r);  // the pass's feed marks
  for (double z = -11.2; z < -2.0; z += 0.5) EXPECT_NEAR(radius_at(tip, z), 18.0, rz) << z;
  for (double z = -12.05; z > -14.9; z -= 0.25) EXPECT_EQ(radius_at(tip, z), 20.0) << z;
  opt.table_tools = {TableTool{.number = 1, .orientation = 6}};
  const auto low = predict(prog, programmed(prog), e, opt);
  EXPECT_NEAR(radius_at(low, -12.0), 18.0, rz);  // the nose's centre, where the tip's was
  EXPECT_LT(radius_at(low, -12.5), 19.0);           // the face r deeper
  EXPECT_EQ(radius_at(low, -12.0 - r - 0.05), 20.0);
}

// The prediction cuts with the tool's own nose (tool_geometry): the tool table's D/2, not the
// scenario's. The pass at X18 ends at Z-12 with the tip of Q2, the nose's centre at
// (18 + r, -12 + r): the shoulder's fillet is its circle, R(z) = 18 + r - sqrt(r² - (z - z_c)²)
// over Z-12 … z_c, with r = D/2 of T1 D0.8 and D1.6 alike; the tool file's nose wins over the
// table's.
TEST(Predict, TheToolTablesNoseCutsTheShoulderFillet) {
  const auto& e = step_allowance();
  io::CanonProgram prog = rapid_and_pass(25.0, 5.0);
  CanonMove m = prog.moves.back();
  m.x0 = 18.0, m.z0 = -12.0, m.x1 = 21.0, m.z1 = -12.0;
  prog.moves.push_back(m);
  for (auto& mv : prog.moves) mv.tool = 1;
  Options opt;
  opt.blends = false;
  for (const double d : {0.8, 1.6}) {
    opt.table_tools = {TableTool{.number = 1, .diameter_mm = d, .orientation = 2}};
    const double r = 0.5 * d, zc = -12.0 + r;
    EXPECT_EQ(tool_geometry(opt, e, 1).nose_radius_mm, r);
    const auto pr = predict(prog, programmed(prog), e, opt);
    int checked = 0;
    for (std::size_t i = 0; i < pr.part_z.size(); ++i) {
      const double dz = pr.part_z[i] - zc;  // the fillet where its slope is below 2
      if (dz > -0.85 * r && dz < -0.2 * r) {
        EXPECT_NEAR(pr.part_r[i], 18.0 + r - std::sqrt(r * r - dz * dz), 0.012)
            << "D" << d << " Z" << pr.part_z[i];
        ++checked;
      }
    }
    EXPECT_GE(checked, 3) << "D" << d;
  }
  opt.tool_specs = {ToolSpec{.number = 1, .nose_radius_mm = 1.2}};
  EXPECT_EQ(tool_geometry(opt, e, 1).nose_radius_mm, 1.2);
  opt.table_tools = {TableTool{.number = 1, .diameter_mm = 0.0, .orientation = 0}};  // no nose
  opt.tool_specs.clear();
  EXPECT_EQ(tool_geometry(opt, e, 1).nose_radius_mm, e.rig.cutting.nose_radius_mm);
  EXPECT_EQ(tool_geometry(opt, e, 1).orientation, e.rig.tool_orientation);  // a point tool
  opt.table_tools[0].diameter_mm = 0.8;
  EXPECT_EQ(tool_geometry(opt, e, 1).orientation, 0);  // Q0 with a nose: its centre
  // The insert's angles: the table's I and J where either is given, else the scenario's.
  auto e2 = e;
  e2.rig.tool_front_angle_deg = 95.0, e2.rig.tool_back_angle_deg = 175.0;
  EXPECT_EQ(tool_geometry(opt, e2, 1).front_angle_deg, 95.0);
  EXPECT_EQ(tool_geometry(opt, e2, 1).back_angle_deg, 175.0);
  opt.table_tools[0].back_angle_deg = 5.0;  // J alone: I is 0, as the table says
  EXPECT_EQ(tool_geometry(opt, e2, 1).front_angle_deg, 0.0);
  EXPECT_EQ(tool_geometry(opt, e2, 1).back_angle_deg, 5.0);
  opt.table_tools[0].front_angle_deg = 85.0;
  EXPECT_EQ(tool_geometry(opt, e2, 1).front_angle_deg, 85.0);
  EXPECT_EQ(tool_geometry(opt, e2, 1).back_angle_deg, 5.0);
}

// With only the force binding, the handbook law inverts: s = (L / (10·Cp·t^x·V^n·Kmp))^(1/y).
TEST(Plan, LargestFeedInvertsTheForceLaw) {
  const auto& e = step_allowance();
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  FeedLimits l;
  l.param = 1600.0;
  l.power_W = l.torque_N_m = 1e12;
  l.feed_min = 0.01;
  l.feed_max = 5.0;
  const double t = 2.5, v = 150.0;
  const auto& mat = e.rig.cutting.material;
  const double kmp = std::pow(mat.strength / mat.strength_base, mat.kmp_exponent);
  const double s =
      std::pow(l.param / (10.0 * mat.Pz.Cp * std::pow(t, mat.Pz.x) * std::pow(v, mat.Pz.n) * kmp),
               1.0 / mat.Pz.y);
  const auto [f, why] = largest_feed(cut, cutting::ForceParameter::Pz, l, t, v, 1.0, 1.0, 18.0);
  EXPECT_NEAR(f, s, 1e-6 * s);
  EXPECT_EQ(why, "force");
  l.torque_N_m = 10.0;  // Pz·(x + t) ≤ 10 N·m binds first
  const auto [f2, why2] = largest_feed(cut, cutting::ForceParameter::Pz, l, t, v, 1.0, 1.0, 18.0);
  EXPECT_LT(f2, f);
  EXPECT_EQ(why2, "torque");
  EXPECT_NEAR(cut.forces({t, f2, v, 1.0, 1.0}).Pz * 20.5e-3, 10.0, 1e-4);
}

// cautious_roughing.ngc on step_allowance.toml through LinuxCNC's interpreter: the rewrite keeps
// every piece within the feed bounds and the predicted per-revolution force within the limit,
// and shortens the cycle; the profile's kept line stays as written.
TEST(Optimize, RewriteRespectsTheLimits) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto& e = step_allowance();
  const auto opt = options();
  const auto p = read_program(LATHECTL_SOURCE_DIR "/examples/linuxcnc/cautious_roughing.ngc", opt);
  const auto r = optimize(p, e, opt);
  const auto& c = e.rig.controller;
  for (std::size_t mi = 0; mi < p.canon.moves.size(); ++mi) {
    if (p.canon.moves[mi].kind == CanonMove::Kind::Traverse) continue;
    for (const auto& pc : r.optimized[mi]) {
      EXPECT_GE(pc.feed, c.feed_min_mm_per_rev - 1e-12);
      EXPECT_LE(pc.feed, c.feed_max_mm_per_rev + 1e-12);
    }
  }
  const auto& s = r.after.s;
  const auto rev = control::per_revolution_mean(s.param, s.rpm, s.dt_s);
  for (double x : rev) EXPECT_LE(x, c.load_limit);
  EXPECT_LT(r.after.cycle_time_s, 0.75 * r.before.cycle_time_s);
  EXPECT_FALSE(r.splits_dropped);
  EXPECT_GT(r.blocks_changed, 0);

  const auto q = read_program(LATHECTL_SOURCE_DIR "/examples/linuxcnc/profile_arcs.ngc", opt);
  const auto rq = optimize(q, e, opt);
  std::string kept;
  for (const auto& l : q.lines)
    if (keep_marked(l)) kept = l;
  ASSERT_FALSE(kept.empty());
  EXPECT_NE(rq.ngc.find("\n" + kept + "\n"), std::string::npos);
}

TEST(Optimize, InterpreterErrorNamesFileAndLine) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  try {
    (void)interpret({"G18 G21", "G1 X10 Z5 F100", "G2 X3 Z1 I1 J100", "M2"}, "bad.ngc", options());
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.ngc:3:", 0), 0u) << e.what();
  }
}

// The planner's acceleration in the predicted cycle time (predict.cpp, acceleration_time):
// against the trapezoid's closed forms, and where a program's planner stops or runs on. The check
// against LinuxCNC itself is in tests/hal/optimize_verify_test.py (the predicted cycle within
// 0.8 s of the measured one, of which about 0.6 s is LinuxCNC starting the program).

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

// A rapid to the start of a G95 pass and the pass: LinuxCNC stops between them (a rapid and a
// feed move are not blended, blend.hpp), and the rapid alone loses v/a; the pass split into
// three pieces of one feed runs on through the splits, as LinuxCNC runs tangent segments.
TEST(Accel, SplitPiecesRunOnAndARapidStopsBeforeTheCut) {
  const io::CanonProgram prog = rapid_and_pass(60.0, 60.0);
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

namespace lathectl::optimize {
namespace {
// One machine side everywhere: the optimiser's prediction with system E's machine side in the
// loop (Options::adaptive, control::AdaptiveMachine) against `lathectl run` (rig E, the same
// object) on the allowance step, in the windows and to the tolerances LinuxCNC's session test
// holds the rig to (tests/hal/linuxcnc_session_test.py: ±1 % of the limit in force, ±2 % in
// feed): before the collar, on it, after it. Stock z = −machine z (the face at machine Z0).
// Measured: force 1136.2 / 1143.2, 1597.0 / 1599.6, 1137.0 / 1144.8 N; feed on the collar
// 0.1920 / 0.1884 mm/rev (1.9 %: the rig's point tool against the plant's round nose).
TEST(Predict, AdaptiveAgreesWithLathectlRunOnTheAllowanceStep) {
  if (!have_rs274()) GTEST_SKIP() << "needs LinuxCNC's rs274";
  static const auto lib = io::MaterialLibrary::load_default();
  const auto sc =
      systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  const auto& e = sc.get<systems::e_adaptive::Settings>();
  auto opt = options();
  opt.adaptive = true;
  const auto prog = read_program(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.ngc", opt);
  const auto pr = predict(prog.canon, programmed(prog.canon), e, opt);
  EXPECT_EQ(pr.adaptive_alarm, 0);
  ASSERT_EQ(pr.adaptive_feed_rev.size(), pr.s.z.size());

  const auto run = systems::run_scenario(sc);
  std::istringstream csv(run.channels_csv);
  const auto rig = io::read_channels_csv(csv, "channels.csv");
  auto col = [&](const std::string& n) -> const std::vector<double>& {
    for (std::size_t i = 0; i < rig.names.size(); ++i)
      if (rig.names[i] == n) return rig.columns[i];
    throw std::runtime_error("no column " + n);
  };
  const auto &rz = col("z_mm"), &rpass = col("pass"), &rf = col("force_parameter_true"),
             &rs = col("feed_cmd_mm_per_rev");
  const double limit = e.rig.controller.load_limit;
  for (const auto& [name, lo, hi] : {std::tuple{"before", 9.0, 14.0},
                                     std::tuple{"collar", 19.0, 29.0},
                                     std::tuple{"after", 38.0, 48.0}}) {
    double fa = 0, sa = 0, na = 0, fb = 0, sb = 0, nb = 0;
    for (std::size_t i = 0; i < pr.s.z.size(); ++i) {
      const double zs = -pr.s.z[i];
      if (zs < lo || zs > hi || pr.s.depth[i] <= 0.0) continue;
      fa += pr.s.param[i];
      sa += pr.adaptive_feed_rev[i];
      ++na;
    }
    for (std::size_t i = 0; i < rz.size(); ++i) {
      if (rpass[i] != 0.0 || rz[i] < lo || rz[i] > hi) continue;
      fb += rf[i];
      sb += rs[i];
      ++nb;
    }
    ASSERT_GT(na, 0);
    ASSERT_GT(nb, 0);
    fa /= na, sa /= na, fb /= nb, sb /= nb;
    EXPECT_NEAR(fa, fb, 0.01 * limit) << name << ": force, optimize / lathectl run";
    EXPECT_NEAR(sa, sb, 0.02 * sb) << name << ": feed, optimize / lathectl run";
  }
}
}  // namespace
}  // namespace lathectl::optimize
