// The machine's INI in the prediction (issue 47): LinuxCNC's travel to [EMCIO]TOOL_CHANGE_POSITION
// at each M6 (emccanon.cc CHANGE_TOOL: rs274 does not print it) against the trapezoid's closed
// form, and where the tool starts on a user's machine ([JOINT_n]HOME, when clear of the blank).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "lathectl/io/canon.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/linuxcnc_ini.hpp"
#include "lathectl/io/materials.hpp"
#include "optimize/optimize.hpp"
#include "systems/registry.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

const systems::e_adaptive::Settings& tc_bar() {
  static const auto lib = io::MaterialLibrary::load_default();
  static const auto sc =
      systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  return sc.get<systems::e_adaptive::Settings>();
}

io::LatheMachine tc_sim_lathe() {
  const std::string f = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  return io::lathe_machine(io::parse_linuxcnc_ini(read_text(f), f));
}

std::string tc_error(const std::string& text) {
  try {
    (void)io::lathe_machine(io::parse_linuxcnc_ini(text, "m.ini"));
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ToolChange, IniPositionAndHome) {
  const auto sim = tc_sim_lathe();
  ASSERT_TRUE(sim.tool_change_x && sim.tool_change_z);
  EXPECT_DOUBLE_EQ(*sim.tool_change_x, 60.0);  // TOOL_CHANGE_POSITION = 60 0 60
  EXPECT_DOUBLE_EQ(*sim.tool_change_z, 60.0);
  EXPECT_DOUBLE_EQ(sim.home_x, 60.0);
  EXPECT_EQ(sim.home_z_key, "[JOINT_1]HOME");  // trivkins coordinates=xz: Z is joint 1
  // LinuxCNC's inch sim/axis/lathe.ini: "2 0 1" in inches, no HOME (homes at 0).
  const auto inch = io::lathe_machine(io::parse_linuxcnc_ini(
      "[TRAJ]\nLINEAR_UNITS = inch\n[EMCIO]\n       TOOL_CHANGE_POSITION = 2 0 1\n"
      "[KINS]\nKINEMATICS = trivkins coordinates=xz\n[JOINT_0]\nHOME_SEARCH_VEL = 5.0\n",
      "lathe.ini"));
  EXPECT_DOUBLE_EQ(*inch.tool_change_x, 50.8);
  EXPECT_DOUBLE_EQ(*inch.tool_change_z, 25.4);
  EXPECT_EQ(inch.home_x_line, 0);
  EXPECT_DOUBLE_EQ(inch.home_z, 0.0);
  // Without coordinates=, trivkins' identity: Z is joint 2.
  const auto ident = io::lathe_machine(
      io::parse_linuxcnc_ini("[TRAJ]\nLINEAR_UNITS = mm\n[JOINT_2]\nHOME = -7\n", "i.ini"));
  EXPECT_DOUBLE_EQ(ident.home_z, -7.0);
  EXPECT_EQ(ident.home_z_line, 4);
  // Malformed: file, line, section and key.
  EXPECT_EQ(tc_error("[TRAJ]\nLINEAR_UNITS=mm\n[EMCIO]\nTOOL_CHANGE_POSITION = 60 0\n"),
            "m.ini:4: [EMCIO]TOOL_CHANGE_POSITION = '60 0': expected X Y Z [A B C [U V W]] "
            "(machine coordinates)");
  EXPECT_EQ(tc_error("[TRAJ]\nLINEAR_UNITS=mm\n[EMCIO]\nTOOL_CHANGE_POSITION = 60 0 6O\n"),
            "m.ini:4: [EMCIO]TOOL_CHANGE_POSITION = '60 0 6O': not a number: '6O' "
            "(X Y Z [A B C [U V W]])");
  EXPECT_EQ(tc_error("[TRAJ]\nLINEAR_UNITS=mm\n[JOINT_2]\nHOME_OFFSET = 1\nHOME = far\n"),
            "m.ini:5: [JOINT_2]HOME = 'far': not a number");
  EXPECT_EQ(tc_error("[TRAJ]\nLINEAR_UNITS=mm\n[JOINT_0]\nHOME_OFFSET = x\n"),
            "m.ini:4: [JOINT_0]HOME_OFFSET = 'x': not a number");
}

// rs274's commands for "T1 M6 / G0 X25 Z5 / T2 M6 / G0 X30 Z10" from the sim's home (60, 60).
constexpr const char* kTwoChanges =
    "1 N..... SELECT_PLANE(CANON_PLANE_XZ)\n"
    "2 N..... COMMENT(\"lathectl-line 1\")\n"
    "3 N..... SELECT_TOOL(1)\n"
    "4 N..... CHANGE_TOOL(1)\n"
    "5 N..... COMMENT(\"lathectl-line 2\")\n"
    "6 N..... STRAIGHT_TRAVERSE(25.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)\n"
    "7 N..... COMMENT(\"lathectl-line 3\")\n"
    "8 N..... SELECT_TOOL(2)\n"
    "9 N..... CHANGE_TOOL(2)\n"
    "10 N..... COMMENT(\"lathectl-line 4\")\n"
    "11 N..... STRAIGHT_TRAVERSE(30.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)\n";

TEST(ToolChange, TheTravelIsARapidToThePositionAndTheNextMoveStartsThere) {
  const auto sim = tc_sim_lathe();
  const io::ToolChangePosition tc{*sim.tool_change_x, *sim.tool_change_z};
  const auto p = io::parse_canon(kTwoChanges, "t.ngc", 60.0, 60.0, tc);
  // the first M6 is at the position already: no travel
  ASSERT_EQ(p.moves.size(), 3U);
  const auto& t = p.moves[1];
  EXPECT_TRUE(t.tool_change);
  EXPECT_EQ(t.kind, CanonMove::Kind::Traverse);
  EXPECT_EQ(t.line, 3);
  EXPECT_EQ(t.tool, 1);  // the tool leaving
  EXPECT_TRUE(t.stop_before);
  EXPECT_DOUBLE_EQ(t.x0, 25.0);
  EXPECT_DOUBLE_EQ(t.z1, 60.0);
  EXPECT_TRUE(p.moves[2].stop_before);
  EXPECT_DOUBLE_EQ(p.moves[2].x0, 60.0);
  EXPECT_DOUBLE_EQ(p.moves[2].z0, 60.0);
  EXPECT_EQ(p.moves[2].tool, 2);
  // In machine coordinates: a work offset in force moves it in the program's.
  const auto g = io::parse_canon(
      "0 N..... SET_G5X_OFFSET(1, 2.0000, 0.0000, -100.0000, 0, 0, 0)\n" + std::string(kTwoChanges),
      "t.ngc", 60.0, 60.0, tc);
  ASSERT_TRUE(g.moves[0].tool_change);  // now the first M6 moves too
  EXPECT_DOUBLE_EQ(g.moves[0].x1, 58.0);
  EXPECT_DOUBLE_EQ(g.moves[0].z1, 160.0);
}

// The predicted cycle with the travel, less the one without: the travel P → T and T → Q from rest
// to rest, instead of P → Q, each the trapezoid len/v + v/a (or the triangle 2·√(len/a)) at the
// INI's acceleration and the rapid (the scenario's 4800 mm/min, the INI's 80 mm/s).
TEST(ToolChange, TwoToolsPredictTheTravelAsTheClosedFormTrapezoid) {
  const auto sim = tc_sim_lathe();
  const auto& e = tc_bar();
  Options opt;
  opt.machine.accel_mm_s2 = *sim.max_acceleration_mm_s2;
  const double v = e.rig.rapid_m_per_s * 1000.0, a = opt.machine.accel_mm_s2;
  ASSERT_DOUBLE_EQ(v, *sim.max_velocity_mm_s);
  const auto time = [&](double len) {
    return len >= v * v / a ? len / v + v / a : 2.0 * std::sqrt(len / a);
  };
  const auto without = io::parse_canon(kTwoChanges, "t.ngc", 60.0, 60.0);
  const auto with = io::parse_canon(kTwoChanges, "t.ngc", 60.0, 60.0,
                                    io::ToolChangePosition{60.0, 60.0});
  const double t0 = predict(without, programmed(without), e, opt).cycle_time_s;
  const double t1 = predict(with, programmed(with), e, opt).cycle_time_s;
  const double pt = std::hypot(35.0, 55.0), tq = std::hypot(30.0, 50.0), pq = std::hypot(5.0, 5.0);
  EXPECT_NEAR(t1 - t0, time(pt) + time(tq) - time(pq), 1e-9);
  EXPECT_GT(t1 - t0, 1.5);  // the 1.0–2.8 s a change cost the cycle check
}

// LinuxCNC's interpreter on the sample lathe (TOOL_CHANGE_POSITION = 60 0 60): the travel is
// added at the second M6, on its line.
TEST(ToolChange, InterpretAddsTheTravelOfTheSimulatedLathe) {
  if (!std::filesystem::exists("/usr/bin/rs274")) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  Options opt;
  opt.ini = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  opt.tool_table = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.tbl";
  opt.rs274 = "/usr/bin/rs274";
  opt.start_x_mm = opt.start_z_mm = 60.0;
  const auto p = interpret({"G18 G21 G90", "T1 M6", "G0 X25 Z5", "T2 M6", "G0 X30 Z10", "M2"},
                           "two.ngc", opt);
  int travels = 0;
  for (const auto& m : p.moves)
    if (m.tool_change) {
      ++travels;
      EXPECT_EQ(m.line, 4);
      EXPECT_DOUBLE_EQ(m.x1, 60.0);
      EXPECT_DOUBLE_EQ(m.z1, 60.0);
    }
  EXPECT_EQ(travels, 1);
}

// A travel through the blank is refused as LinuxCNC's, at the M6's line: T1 cuts Ø40 → Ø36 from
// Z2 to Z-12, then the change goes to (60, -100) behind it, through the uncut bar and its collar.
TEST(ToolChange, ATravelThroughTheBlankIsNamedAsSuch) {
  const std::string canon =
      "1 N..... SELECT_PLANE(CANON_PLANE_XZ)\n"
      "2 N..... SET_FEED_MODE(0, 1)\n"
      "3 N..... SET_FEED_RATE(0.3000)\n"
      "4 N..... SET_SPINDLE_SPEED(0, 1194.0000)\n"
      "5 N..... START_SPINDLE_CLOCKWISE(0)\n"
      "6 N..... COMMENT(\"lathectl-line 2\")\n"
      "7 N..... STRAIGHT_TRAVERSE(18.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)\n"
      "8 N..... COMMENT(\"lathectl-line 3\")\n"
      "9 N..... STRAIGHT_FEED(18.0000, 0.0000, -12.0000, 0.0000, 0.0000, 0.0000)\n"
      "10 N..... COMMENT(\"lathectl-line 4\")\n"
      "11 N..... SELECT_TOOL(2)\n"
      "12 N..... CHANGE_TOOL(2)\n";
  Program p;
  p.file = "behind.ngc";
  p.lines = {"G18 G21 G95 M3 S1194", "G0 X18 Z2", "G1 Z-12 F0.3", "T2 M6"};
  p.canon = io::parse_canon(canon, p.file, 60.0, 60.0, io::ToolChangePosition{60.0, -100.0});
  try {
    (void)optimize(p, tc_bar(), Options{});
    FAIL() << "no error";
  } catch (const io::InputError& ex) {
    EXPECT_EQ(std::string(ex.what()).rfind("behind.ngc:4: LinuxCNC's travel to "
                                           "[EMCIO]TOOL_CHANGE_POSITION at the M6 drives the tool "
                                           "through the blank (",
                                           0),
              0U)
        << ex.what();
  }
}

// The start on a user's machine: its home when clear of the blank (Ø40 with a Ø44 collar from the
// face at machine Z0, a 0.8 mm nose), else the simulated lathe's start and one line naming the INI and its keys.
TEST(ToolChange, HomeIsTakenOnlyClearOfTheBlank) {
  const auto& e = tc_bar();
  Options opt;  // start 60, 60; z origin 0
  const auto start = [&](const std::string& ini) {
    return machine_start(io::lathe_machine(io::parse_linuxcnc_ini(ini, "lathe.ini")), "lathe.ini",
                         e, opt);
  };
  // LinuxCNC's sim/axis/lathe.ini: no HOME, so X0 Z0, the face's centre.
  const auto lcnc = start("[TRAJ]\nLINEAR_UNITS = inch\n[KINS]\nKINEMATICS = trivkins coordinates=xz\n");
  EXPECT_FALSE(lcnc.from_ini);
  EXPECT_DOUBLE_EQ(lcnc.x_mm, 60.0);
  EXPECT_DOUBLE_EQ(lcnc.z_mm, 60.0);
  EXPECT_EQ(lcnc.note, "lathe.ini: [JOINT_0]HOME absent (0), [JOINT_1]HOME absent (0): LinuxCNC "
                       "homes the tool at X0 Z0 inch, in the blank (radius up to 22 mm, face at "
                       "machine Z0 mm; the simulated lathe has no work offsets); it starts at X60 "
                       "Z60 mm as without --ini");
  // Above the bar's radius by more than the nose's width: taken.
  const auto above = start("[TRAJ]\nLINEAR_UNITS = mm\n[KINS]\nKINEMATICS = trivkins coordinates=xz\n"
                           "[JOINT_0]\nHOME = 23.7\n[JOINT_1]\nHOME = -30\n");
  EXPECT_TRUE(above.from_ini);
  EXPECT_DOUBLE_EQ(above.x_mm, 23.7);
  EXPECT_DOUBLE_EQ(above.z_mm, -30.0);
  // In front of the face: taken; on the bar's surface: not, naming the lines.
  EXPECT_TRUE(start("[TRAJ]\nLINEAR_UNITS = mm\n[JOINT_2]\nHOME = 1.7\n").from_ini);
  const auto on = start("[TRAJ]\nLINEAR_UNITS = mm\n[KINS]\nKINEMATICS = trivkins coordinates=xz\n"
                        "[JOINT_0]\nHOME = 22\n[JOINT_1]\nHOME = -30\n");
  EXPECT_FALSE(on.from_ini);
  EXPECT_NE(on.note.find("[JOINT_0]HOME (line 6), [JOINT_1]HOME (line 8)"), std::string::npos)
      << on.note;
}

}  // namespace
}  // namespace lathectl::optimize
