// lathectl optimize on what a programmer must not meet: threads timed by the modal F word,
// rapids through the blank passed over, moves beyond the machine's soft limits, lines the line
// marker pushed past rs274's length limit, an interpreter that never ends. All need LinuxCNC's
// rs274 (skipped without it).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <list>
#include <string>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "optimize/optimize.hpp"
#include "optimize/path.hpp"
#include "optimize/text.hpp"
#include "systems/registry.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

const systems::e_adaptive::Settings& scenario(const std::string& file) {
  static const auto lib = io::MaterialLibrary::load_default();
  static std::list<std::pair<std::string, io::Scenario>> cache;  // references stay valid
  for (const auto& [f, sc] : cache)
    if (f == file) return sc.get<systems::e_adaptive::Settings>();
  cache.emplace_back(file, systems::load_scenario(file, lib));
  return cache.back().second.get<systems::e_adaptive::Settings>();
}
const systems::e_adaptive::Settings& step_allowance() {
  return scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml");
}

bool have_rs274() { return std::filesystem::exists("/usr/bin/rs274"); }
Options options() {
  Options o;
  o.ini = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  o.rs274 = "/usr/bin/rs274";
  return o;
}

std::string write_temp(const std::string& name, const std::vector<std::string>& lines) {
  const auto dir = std::filesystem::temp_directory_path() / "lathectl-hostile-test";
  std::filesystem::create_directories(dir);
  const auto p = dir / name;
  std::ofstream f(p);
  for (const auto& l : lines) f << l << '\n';
  return p.string();
}

// The M36x2 thread, G7 diameters: drive line Ø38 from Z1 to Z-29, peak Ø36 (I-2), first
// pass J0.4, full depth K2.454 (1.227 mm on the radius: 0.6134·P), degression R1.5, one spring
// pass; 1000 rpm. `before` is what precedes it (the modal F, or none).
std::vector<std::string> thread_program(const std::string& before) {
  std::vector<std::string> l{"G18 G21 G40 G90 G95 G7", "T1 M6", "M3 S1000", "G0 X54 Z2"};
  if (!before.empty()) l.push_back(before);
  for (const char* s : {"G0 X38 Z1", "G76 P2 Z-29 I-2 J0.4 K2.454 R1.5 Q29.5 H1", "G0 X60 Z60",
                        "M2"})
    l.emplace_back(s);
  return l;
}

// Time the prediction spends in spindle-synchronised moves, and their number.
std::pair<double, int> thread_time(const io::CanonProgram& prog, const Prediction& pr) {
  double t = 0.0;
  for (std::size_t i = 0; i < pr.s.move.size(); ++i)
    if (prog.moves[static_cast<std::size_t>(pr.s.move[i])].synced) t += pr.s.dt[i];
  int n = 0;
  for (const auto& m : prog.moves) n += m.synced ? 1 : 0;
  return {t, n};
}

// A thread advances its pitch per revolution (LinuxCNC synchronises it to the spindle): each
// pass takes length / (P·n/60), whatever F was programmed before it. The passes are LinuxCNC's
// (G-code reference, G76): pass k at depth J·k^(1/R) beyond the peak while that is short of K,
// then one at K, then H spring passes at K — for this thread 15 + 1 + 1 = 17.
TEST(Threads, TimedByPitchTimesRpmWhateverTheModalFeed) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto& e = step_allowance();
  Options opt = options();
  int passes = 0;
  for (int k = 1; 0.4 * std::pow(k, 1.0 / 1.5) < 2.454; ++k) ++passes;
  passes += 1 + 1;
  ASSERT_EQ(passes, 17);
  double first = -1.0;
  for (const std::string before : {"G1 X52 F0.05", "G1 X52 F0.3", ""}) {
    const auto prog = interpret(thread_program(before), "thread.ngc", opt);
    const auto pr = predict(prog, programmed(prog), e, opt);
    const auto [t, n] = thread_time(prog, pr);
    EXPECT_EQ(n, passes) << before;
    double expected = 0.0;
    for (const auto& m : prog.moves)
      if (m.synced) expected += move_length(m) / (2.0 * 1000.0 / 60.0);
    EXPECT_NEAR(t, expected, 1e-9) << before;
    // About 0.9 s a pass over the 30 mm drive line, 15 s in all (591.6 s when timed by F0.05).
    EXPECT_NEAR(t, 14.95, 0.02) << before;
    if (first < 0.0) first = t;
    EXPECT_NEAR(t, first, 1e-9) << before;
  }
}

// The thread lines of a whole part stay byte-identical in optimized.ngc, with nothing inserted
// before them; and the part's facing, roughing and finishing lines are still optimised.
TEST(Threads, LeftByteIdenticalInTheUsersPart) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto& e = scenario(LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part_c45.toml");
  Options opt = options();
  const auto p = read_program(LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part.ngc", opt);
  const auto r = optimize(p, e, opt);
  std::vector<std::string> out;
  for (std::size_t a = 0, b; a < r.ngc.size(); a = b + 1) {
    b = r.ngc.find('\n', a);
    out.push_back(r.ngc.substr(a, b - a));
  }
  int threads = 0;
  for (std::size_t li = 0; li < p.lines.size(); ++li) {
    if (p.lines[li].rfind("G76", 0) != 0) continue;
    ++threads;
    std::size_t at = 0;
    while (at < out.size() && out[at] != p.lines[li]) ++at;
    ASSERT_LT(at, out.size()) << p.lines[li];
    ASSERT_GT(at, 0u);
    EXPECT_EQ(out[at - 1], p.lines[li - 1]);
    EXPECT_EQ(r.actions[li].kind, LineAction::Kind::Keep);
  }
  EXPECT_EQ(threads, 1);
  // Its thread takes pitch × rpm: about 15 s of the cycle, not the 591.6 s F0.05 gave.
  const auto [t, n] = thread_time(p.canon, r.before);
  EXPECT_EQ(n, 17);
  EXPECT_NEAR(t, 14.95, 0.02);
}

// A valid line just short of rs274's limit: the marker would push it past, so it goes on a line
// of its own before it, and the moves still carry the line's number.
TEST(Interpret, LongLineKeepsItsNumberWithoutBreakingTheLimit) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  std::string longline = "G1 Z-20 F0.2";
  longline += std::string(kMaxLineChars - longline.size() - 12, ' ') + "(a comment)";
  ASSERT_LE(longline.size(), kMaxLineChars);
  const std::vector<std::string> lines{"G18 G21 G95", "M3 S1000", "G0 X15 Z2", longline, "M2"};
  const auto marked = marked_lines(lines, 0.0);
  for (const auto& l : marked) EXPECT_LE(l.size(), kMaxLineChars) << l;
  const auto prog = interpret(lines, "long.ngc", options());
  ASSERT_FALSE(prog.moves.empty());
  EXPECT_EQ(prog.moves.back().line, 4);
  EXPECT_EQ(prog.moves.back().kind, CanonMove::Kind::Line);
  EXPECT_EQ(prog.moves.front().line, 3);
}

// LinuxCNC refuses a program that leaves the soft limits ([AXIS_Z] MIN_LIMIT = -400 in the
// simulated lathe's INI); so does optimize, naming the line and the limit.
TEST(Interpret, MoveBeyondTheSoftLimitIsAnError) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto file = write_temp("soft_limit.ngc", {"G18 G21 G95", "M3 S1000", "G0 X15 Z2",
                                                  "G1 Z-500 F0.2", "G0 X30", "M2"});
  try {
    (void)read_program(file, options());
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("soft_limit.ngc:4:"), std::string::npos) << w;
    EXPECT_NE(w.find("[AXIS_Z] MIN_LIMIT"), std::string::npos) << w;
    EXPECT_NE(w.find("-500"), std::string::npos) << w;
  }
  // Inside the limits (Z-399), the same program is read.
  const auto ok = write_temp("soft_limit_ok.ngc", {"G18 G21 G95", "M3 S1000", "G0 X15 Z2",
                                                   "G1 Z-399 F0.2", "G0 X30", "M2"});
  EXPECT_NO_THROW((void)read_program(ok, options()));
}

// An endless o-word loop: rs274 is stopped at the time limit, or sooner at the output limit,
// with an error that says so; nothing of it is left running.
TEST(Interpret, EndlessLoopEndsWithAClearError) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const std::vector<std::string> loop{"G18 G21 G95",       "M3 S1000",   "G0 X15 Z2",
                                      "o100 while [1 GT 0]", "G1 Z-10 F0.2", "G1 Z0",
                                      "o100 endwhile",     "M2"};
  Options opt = options();
  opt.interp_timeout_s = 1.0;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    (void)interpret(loop, "loop.ngc", opt);
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("loop.ngc"), std::string::npos) << w;
    EXPECT_TRUE(w.find("did not finish within 1 s") != std::string::npos ||
                w.find("wrote more than") != std::string::npos)
        << w;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  opt.interp_timeout_s = 60.0;
  opt.interp_output_max_bytes = 1u << 20;
  try {
    (void)interpret(loop, "loop.ngc", opt);
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wrote more than 1.04858 MB"), std::string::npos)
        << e.what();
  }
}

// A rapid into the bar (step_allowance.toml: Ø40 from the face at Z0): an error naming the line;
// allowed, the feed moves from the rapid on keep their programmed feeds (the stock model has the
// rapid's track cut away and would take the next cut for air), and the lines before are optimised.
TEST(Optimize, RapidThroughTheBlankIsAnErrorUnlessAllowed) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto file = write_temp(
      "rapid.ngc", {"G18 G21 G95", "M3 S1194", "G0 X25 Z2", "G0 X17", "G1 Z-50 F0.15",
                    "G0 X25", "G0 Z2", "G0 X15 Z-20", "G1 Z-50 F0.15", "G0 X25", "M2"});
  Options opt = options();
  const auto p = read_program(file, opt);
  try {
    (void)optimize(p, step_allowance(), opt);
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("rapid.ngc:8:"), std::string::npos) << w;
    EXPECT_NE(w.find("through the blank"), std::string::npos) << w;
  }
  opt.allow_rapid_in_material = true;
  const auto r = optimize(p, step_allowance(), opt);
  EXPECT_GT(r.before.rapid_in_material_s, 0.0);
  EXPECT_EQ(r.before.rapid_first_line, 8);
  EXPECT_EQ(r.actions[8].kind, LineAction::Kind::Keep);  // line 9, after the rapid
  EXPECT_NE(r.actions[8].why.find("after the rapid"), std::string::npos) << r.actions[8].why;
  EXPECT_NE(r.actions[4].kind, LineAction::Kind::Keep);  // line 5, before it: optimised
  EXPECT_NE(r.actions[4].kind, LineAction::Kind::None);
  for (std::size_t mi = 0; mi < p.canon.moves.size(); ++mi)
    if (p.canon.moves[mi].line == 9) {
      for (const auto& pc : r.optimized[mi]) EXPECT_DOUBLE_EQ(pc.feed, 0.15);
    }
}

// The user's 3 mm groove (line 37, T2, F0.05): without a word on T2 it keeps its feed (the
// turning insert's law and 1.6 mm nose width would have raised it 9x to feed_max); with the tool
// file it is cut at its insert's width — Pz = the law at b = 3 mm, chip = feed per revolution —
// and fed within the insert's range [0.02, 0.08].
TEST(Tools, GroovePlungeAtItsWidthWithinItsFeedRange) {
  if (!have_rs274()) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto& e = scenario(LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part_c45.toml");
  Options opt = options();
  const auto p = read_program(LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part.ngc", opt);
  constexpr int kGroove = 37;
  ASSERT_NE(p.lines[kGroove - 1].find("G1 X32 F0.05"), std::string::npos);
  auto groove_feeds = [&](const Result& r) {
    std::vector<double> f;
    for (std::size_t mi = 0; mi < p.canon.moves.size(); ++mi)
      if (p.canon.moves[mi].line == kGroove)
        for (const auto& pc : r.optimized[mi]) f.push_back(pc.feed);
    return f;
  };
  const auto plain = optimize(p, e, opt);
  EXPECT_EQ(plain.actions[kGroove - 1].kind, LineAction::Kind::Keep);
  for (double f : groove_feeds(plain)) EXPECT_DOUBLE_EQ(f, 0.05);

  const std::string file = LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part_tools.toml";
  opt.tool_specs = read_tool_file(io::read_input_file(file, "a tool file", io::kMaxTomlBytes), file);
  const auto r = optimize(p, e, opt);
  const auto feeds = groove_feeds(r);
  ASSERT_FALSE(feeds.empty());
  for (double f : feeds) {
    EXPECT_GE(f, 0.02);
    EXPECT_LE(f, 0.08);
  }
  // Its predicted force is the law at the insert's width, sample by sample.
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  int checked = 0;
  for (std::size_t i = 0; i < r.after.s.move.size(); ++i) {
    const auto& m = p.canon.moves[static_cast<std::size_t>(r.after.s.move[i])];
    if (m.line != kGroove || !(r.after.s.depth[i] > 0.0) || !(r.after.s.feed_rev[i] > 0.0)) continue;
    const auto f = cut.forces({3.0, r.after.s.feed_rev[i], r.after.s.speed[i],
                               r.after.s.strength[i], r.after.s.wear[i]});
    EXPECT_NEAR(r.after.s.pz[i], f.Pz, 1e-9 * f.Pz);
    EXPECT_LE(r.after.s.param[i], e.rig.controller.load_limit);
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // The thread's tool (T10, threading) leaves the thread alone.
  ASSERT_EQ(p.lines[42].rfind("G76", 0), 0u);
  EXPECT_EQ(r.actions[42].kind, LineAction::Kind::Keep);
}

TEST(Tools, FileErrorsNameFileLineAndKey) {
  auto error = [](const std::string& text) {
    try {
      (void)read_tool_file(text, "tools.toml");
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto bad_kind = error("[[tool]]\nnumber = 2\nkind = \"knurling\"\n");
  EXPECT_NE(bad_kind.find("tools.toml:3"), std::string::npos) << bad_kind;
  EXPECT_NE(bad_kind.find("kind"), std::string::npos) << bad_kind;
  const auto no_width = error("[[tool]]\nnumber = 2\nkind = \"grooving\"\n");
  EXPECT_NE(no_width.find("insert_width_mm"), std::string::npos) << no_width;
  const auto range = error(
      "[[tool]]\nnumber = 2\nkind = \"turning\"\nfeed_min_mm_per_rev = 0.3\n"
      "feed_max_mm_per_rev = 0.2\n");
  EXPECT_NE(range.find("feed_min_mm_per_rev < feed_max_mm_per_rev"), std::string::npos) << range;
  const auto unknown = error("[[tool]]\nnumber = 2\nkind = \"turning\"\nwidth = 3\n");
  EXPECT_NE(unknown.find("width"), std::string::npos) << unknown;
  const auto ok = read_tool_file(
      "[[tool]]\nnumber = 2\nkind = \"parting\"\ninsert_width_mm = 2.5\n", "tools.toml");
  ASSERT_EQ(ok.size(), 1u);
  EXPECT_TRUE(ok[0].plunge());
  EXPECT_DOUBLE_EQ(ok[0].insert_width_mm, 2.5);
}

// LinuxCNC's tool table (the simulated lathe's, hal/config/lathectl-lathe.tbl): D is the nose's
// diameter, I/J the insert's front and back angle, Q its orientation; the tool file fills only
// what the table lacks, and a disagreement names both files.
TEST(Tools, LinuxCncToolTableFillsTheNoseAndMustAgree) {
  const std::string tbl = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.tbl";
  const auto table = read_tool_table(io::read_input_file(tbl, "a tool table", 1 << 20), tbl);
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(table[0].number, 1);
  EXPECT_DOUBLE_EQ(table[0].diameter_mm, 1.6);  // the examples' 0.8 mm nose
  EXPECT_DOUBLE_EQ(table[0].front_angle_deg, 85.0);  // a CNMG in a 95° holder: I85 J5
  EXPECT_DOUBLE_EQ(table[0].back_angle_deg, 5.0);
  EXPECT_EQ(table[0].orientation, 2);  // a right-hand turning tool: the tip at the nose's -X -Z corner
  EXPECT_EQ(table[1].line, 2);
  EXPECT_DOUBLE_EQ(table[2].diameter_mm, 0.0);  // T10: "zero diameter"

  auto specs = read_tool_file(
      "[[tool]]\nnumber = 2\nkind = \"grooving\"\ninsert_width_mm = 3.0\n"
      "[[tool]]\nnumber = 10\nkind = \"threading\"\nnose_radius_mm = 0.1\n",
      "tools.toml");
  apply_tool_table(specs, table, "tools.toml", tbl);
  EXPECT_DOUBLE_EQ(specs[0].nose_radius_mm, 0.4);  // D0.8 / 2: the table fills it
  EXPECT_DOUBLE_EQ(specs[0].front_angle_deg, 85.0);
  EXPECT_EQ(specs[0].orientation, 2);
  EXPECT_DOUBLE_EQ(specs[1].nose_radius_mm, 0.1);  // D0: the table lacks it, the file gives it

  auto wrong = read_tool_file(
      "[[tool]]\nnumber = 2\nkind = \"grooving\"\ninsert_width_mm = 3.0\nnose_radius_mm = 0.2\n",
      "tools.toml");
  try {
    apply_tool_table(wrong, table, "tools.toml", tbl);
    ADD_FAILURE() << "a nose radius of 0.2 mm against D0.8 passed";
  } catch (const io::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("tools.toml"), std::string::npos) << m;
    EXPECT_NE(m.find("lathectl-lathe.tbl:2"), std::string::npos) << m;
  }
  auto table_error = [](const std::string& text) {
    try {
      (void)read_tool_table(text, "t.tbl");
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(table_error("; tools\nT1 P1 D0.8\nT2 P2 Dx\n").find("t.tbl:3"), std::string::npos);
  EXPECT_NE(table_error("T1 P1 Q12\n").find("orientation"), std::string::npos);
  EXPECT_NE(table_error("T1 P1\nT1 P2\n").find("first on line 1"), std::string::npos);
  EXPECT_EQ(table_error("\n; only comments\nT5 P5 D1.2 ; a comment with K words\n"), "no error");
}

// The duplicate checks are linear (issue 49: 10⁵ tools took minutes, each against all before
// it): a 10⁵-tool table and a 2·10⁴-tool file, the repeated tool last, named with its first line.
TEST(OptimizeHostile, DuplicateToolsFoundInLinearTime) {
  std::string table, file;
  for (int t = 1; t <= 100000; ++t) table += "T" + std::to_string(t) + " P1 D0.8\n";
  table += "T7 P1 D0.4\n";
  try {
    (void)read_tool_table(table, "t.tbl");
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.tbl:100001: tool 7 again (first on line 7)"),
              std::string::npos) << e.what();
  }
  for (int t = 0; t < 20000; ++t)
    file += "[[tool]]\nnumber = " + std::to_string(t) + "\nkind = \"turning\"\n";
  file += "[[tool]]\nnumber = 19999\nkind = \"turning\"\n";
  try {
    (void)read_tool_file(file, "tools.toml");
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tool 19999 twice"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lathectl::optimize
