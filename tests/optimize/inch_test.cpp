// lathectl optimize on inch programs (G20): rs274 prints an inch program's lengths, feeds and
// thread pitches in inches and its G96 speed in feet per minute; the canon reader converts each
// as LinuxCNC's canon does, and optimized.ngc writes back in the program's units. An inch program
// and its metric twin (each length × 25.4 exactly) give the same optimisation.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "lathectl/io/canon.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/linuxcnc_ini.hpp"
#include "lathectl/io/materials.hpp"
#include "optimize/optimize.hpp"
#include "optimize/text.hpp"
#include "systems/registry.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

// rs274's output for "G18 G20 G95 / G96 D2000 S500 M3 / G64 P0.001 / G92 Z0.1 / G1 X.5 Z0
// F.01 / G33 Z-1 K.05 / G2 X.3 Z-1.2 I0 K-.2 / G21 / G1 X10 F0.2" (linuxcnc-uspace 2.9), trimmed.
constexpr const char* kInchCanon = R"(executing
    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    8 N..... SET_FEED_MODE(0, 1)
   10 N..... SELECT_PLANE(CANON_PLANE_XZ)
   11 N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)
   12 N..... SET_SPINDLE_MODE(0 2000.0000)
   13 N..... SET_SPINDLE_SPEED(0, 500.0000)
   14 N..... START_SPINDLE_CLOCKWISE(0)
   15 N..... SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.001000)
   16 N..... SET_G92_OFFSET(0.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
   17 N..... SET_FEED_RATE(0.0100)
   18 N..... STRAIGHT_FEED(0.5000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
   19 N..... START_SPEED_FEED_SYNC(0.050000,0)
   20 N..... STRAIGHT_FEED(0.5000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
   21 N..... STOP_SPEED_FEED_SYNCH()
   22 N..... ARC_FEED(-1.2000, 0.3000, -1.2000, 0.5000, -1, 0.0000, 0.0000, 0.0000, 0.0000)
   23 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
   24 N..... SET_FEED_RATE(0.2000)
   25 N..... STRAIGHT_FEED(10.0000, 0.0000, -30.4800, 0.0000, 0.0000, 0.0000)
)";

TEST(Inch, CanonIsReadInMillimetres) {
  const auto p = io::parse_canon(kInchCanon, "t.ngc", 60.0, 60.0);
  ASSERT_EQ(p.moves.size(), 4u);
  const auto& cut = p.moves[0];
  EXPECT_DOUBLE_EQ(cut.unit_mm, 25.4);
  EXPECT_DOUBLE_EQ(cut.x1, 12.7);
  EXPECT_DOUBLE_EQ(cut.feed, 0.254);             // 0.01 in/rev
  EXPECT_DOUBLE_EQ(cut.speed, 500.0 * 0.3048);   // G96 S500 ft/min → 152.4 m/min
  EXPECT_DOUBLE_EQ(cut.css_max_rpm, 2000.0);     // D is rpm in either unit
  EXPECT_DOUBLE_EQ(cut.offset_z, 2.54);          // G92 Z0.1
  EXPECT_DOUBLE_EQ(cut.blend_tol_mm, 0.0254);    // G64 P0.001
  EXPECT_DOUBLE_EQ(p.moves[1].pitch_mm, 1.27);   // G33 K.05: 20 threads per inch
  EXPECT_DOUBLE_EQ(p.moves[1].z1, -25.4);
  const auto& arc = p.moves[2];
  EXPECT_DOUBLE_EQ(arc.x1, 7.62);
  EXPECT_DOUBLE_EQ(arc.zc, -30.48);
  EXPECT_DOUBLE_EQ(arc.xc, 12.7);
  // G21 again: millimetres from that command on, the G92 offset as it was set.
  EXPECT_DOUBLE_EQ(p.moves[3].unit_mm, 1.0);
  EXPECT_DOUBLE_EQ(p.moves[3].feed, 0.2);
  EXPECT_DOUBLE_EQ(p.moves[3].x1, 10.0);
  EXPECT_DOUBLE_EQ(p.moves[3].offset_z, 2.54);
}

const systems::e_adaptive::Settings& step_allowance() {
  static const auto lib = io::MaterialLibrary::load_default();
  static const auto sc =
      systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  return sc.get<systems::e_adaptive::Settings>();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// inch_roughing.ngc and metric_roughing.ngc: the same three passes, in inches and in mm.
TEST(Inch, AnInchProgramAndItsMetricTwinGiveTheSameOptimisation) {
  if (!std::filesystem::exists("/usr/bin/rs274")) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  Options opt;
  opt.ini = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  opt.rs274 = "/usr/bin/rs274";
  const std::string dir = LATHECTL_SOURCE_DIR "/tests/optimize/programs/";
  const auto pi = read_program(dir + "inch_roughing.ngc", opt);
  const auto pm = read_program(dir + "metric_roughing.ngc", opt);
  const auto& e = step_allowance();
  const auto ri = optimize(pi, e, opt);
  const auto rm = optimize(pm, e, opt);
  EXPECT_NEAR(ri.before.cycle_time_s, rm.before.cycle_time_s, 1e-9 * rm.before.cycle_time_s);
  EXPECT_NEAR(ri.after.cycle_time_s, rm.after.cycle_time_s, 1e-9 * rm.after.cycle_time_s);
  EXPECT_LT(rm.after.cycle_time_s, 0.5 * rm.before.cycle_time_s);  // 56.7 s → 21.3 s
  EXPECT_EQ(ri.blocks_changed, rm.blocks_changed);
  EXPECT_FALSE(ri.splits_dropped);
  ASSERT_EQ(ri.optimized.size(), rm.optimized.size());
  for (std::size_t k = 0; k < rm.optimized.size(); ++k) {
    ASSERT_EQ(ri.optimized[k].size(), rm.optimized[k].size()) << "move " << k;
    for (std::size_t j = 0; j < rm.optimized[k].size(); ++j)
      EXPECT_NEAR(ri.optimized[k][j].feed, rm.optimized[k][j].feed, 1e-9) << "move " << k;
  }
  // optimized.ngc keeps G20 and writes in/rev: line by line, each F word of the inch rewrite
  // × 25.4 is the metric rewrite's to the rounding of 5 decimals of an inch (1.27e-4 mm/rev)
  // and 4 of a mm.
  EXPECT_NE(ri.ngc.find("G18 G20 G40 G80 G90 G95\n"), std::string::npos);
  EXPECT_NE(ri.ngc.find(" F0.02362 (lathectl: line 9, piece 1 of 3)"), std::string::npos)
      << ri.ngc;  // 0.6 mm/rev (feed_max)
  const auto li = lines_of(ri.ngc), lm = lines_of(rm.ngc);
  ASSERT_EQ(li.size(), lm.size());
  int feeds = 0;
  for (std::size_t k = 0; k < lm.size(); ++k) {
    const auto f = [](const std::string& l) {
      for (const auto& w : words(l))
        if (w.letter == 'F') return std::stod(w.value);
      return -1.0;
    };
    ASSERT_EQ(f(li[k]) < 0.0, f(lm[k]) < 0.0) << li[k] << " | " << lm[k];
    if (f(lm[k]) < 0.0) continue;
    EXPECT_NEAR(f(li[k]) * 25.4, f(lm[k]), 0.5e-5 * 25.4 + 0.5e-4) << li[k] << " | " << lm[k];
    ++feeds;
  }
  EXPECT_EQ(feeds, 5);  // the first pass in three pieces, the other two passes
  // Interpreted again (rs274 prints 4 decimals of an inch: 2.54 µm, 0.00254 mm/rev), the two
  // rewrites run the same path at the same feeds.
  const auto ci = interpret(li, "inch optimized.ngc", opt);
  const auto cm = interpret(lm, "metric optimized.ngc", opt);
  ASSERT_EQ(ci.moves.size(), cm.moves.size());
  constexpr double kPrinted = 0.5e-4 * 25.4 + 0.5e-4;
  for (std::size_t k = 0; k < cm.moves.size(); ++k) {
    EXPECT_DOUBLE_EQ(ci.moves[k].unit_mm, 25.4);
    EXPECT_NEAR(ci.moves[k].x1, cm.moves[k].x1, kPrinted) << "move " << k;
    EXPECT_NEAR(ci.moves[k].z1, cm.moves[k].z1, kPrinted) << "move " << k;
    if (cm.moves[k].kind != CanonMove::Kind::Traverse) {
      EXPECT_NEAR(ci.moves[k].feed, cm.moves[k].feed, kPrinted) << "move " << k;
    }
  }
}

// LinuxCNC's own inch lathe (sim/axis/lathe.ini, written here as it ships, its comments and
// aligned keys included): its limits in mm, the least velocity and acceleration, its table.
TEST(Inch, MachineIniInMillimetres) {
  const auto ini = io::parse_linuxcnc_ini(
      "[TRAJ]\n         COORDINATES = X Z\n        LINEAR_UNITS = inch\n"
      "MAX_LINEAR_VELOCITY = 3.333334\nMAX_LINEAR_ACCELERATION = 20.0\n"
      "#BACK_TOOL_LATHE = 1 #uncomment for back tool lathe\n"
      "[EMCIO]\n                 TOOL_TABLE = lathe.tbl\n"
      "[AXIS_X]\n       MIN_LIMIT = -10.0\n       MAX_LIMIT = 10.0\n    MAX_VELOCITY = 3.333333\n"
      "[AXIS_Z]\n       MIN_LIMIT = -2.0\n       MAX_LIMIT = 4.0\nMAX_ACCELERATION = 20.0\n",
      "lathe.ini");
  const auto m = io::lathe_machine(ini);
  EXPECT_DOUBLE_EQ(m.unit_mm, 25.4);
  EXPECT_DOUBLE_EQ(*m.x_min, -254.0);
  EXPECT_DOUBLE_EQ(*m.z_max, 101.6);
  EXPECT_DOUBLE_EQ(*m.max_velocity_mm_s, 3.333333 * 25.4);  // [AXIS_X]'s, below [TRAJ]'s
  EXPECT_DOUBLE_EQ(*m.max_acceleration_mm_s2, 508.0);
  EXPECT_EQ(m.tool_table, "lathe.tbl");
  EXPECT_EQ(ini.find("AXIS_Z", "MIN_LIMIT")->line, 14);
  // A velocity ≤ 0, MIN_LIMIT above MAX_LIMIT: file, line, section and key.
  const auto err = [](const char* text) {
    try {
      (void)io::lathe_machine(io::parse_linuxcnc_ini(text, "m.ini"));
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(err("[TRAJ]\nLINEAR_UNITS=mm\n[AXIS_Z]\nMAX_VELOCITY = 0\n"),
            "m.ini:4: [AXIS_Z]MAX_VELOCITY = '0': must be > 0");
  EXPECT_EQ(err("[TRAJ]\nLINEAR_UNITS=mm\n[AXIS_X]\nMIN_LIMIT = 5\nMAX_LIMIT = -5\n"),
            "m.ini:4: [AXIS_X]MIN_LIMIT = '5': above its MAX_LIMIT");
  EXPECT_EQ(err("[AXIS_X]\nMIN_LIMIT = 5\n"), "m.ini: [TRAJ]LINEAR_UNITS missing: the "
                                                 "machine's length unit (mm or inch)");
}

}  // namespace
}  // namespace lathectl::optimize
