// lathectl optimize on programs nobody wrote by hand (program_generator.hpp), each on its own
// generated bar of C45, with the tool file that describes T2 (3 mm grooving, 0.02–0.08 mm/rev)
// and T10 (threading) and LinuxCNC's tool table of the simulated lathe (the noses); some roughed
// by G71 and finished by G70, some finished under G42. The invariants a programmer relies on:
//   1. the predicted per-revolution peak of every line optimize changed is within the limit;
//   2. no finishing line is fed faster than written (its roughness at most the programmed one);
//   3. thread lines stay byte-identical;
//   4. every plunge is fed within its tool's feed range (or as written);
//   5. the optimised program, interpreted again, follows the original path.
// Needs LinuxCNC's rs274 (skipped without it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/control/per_revolution.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "optimize/optimize.hpp"
#include "optimize/path.hpp"
#include "optimize/program_generator.hpp"
#include "systems/registry.hpp"

namespace lathectl::optimize {
namespace {

using io::CanonMove;

// Does `b` run along `a`: every move of a (zero-length ones left out), in order, by moves of the
// same kind (rapid or feed) whose ends lie on it, within the programs' 4 decimals.
std::string path_difference(const io::CanonProgram& a, const io::CanonProgram& b) {
  std::vector<const CanonMove*> ma, mb;
  for (const auto& m : a.moves)
    if (move_length(m) > 1e-6) ma.push_back(&m);
  for (const auto& m : b.moves)
    if (move_length(m) > 1e-6) mb.push_back(&m);
  constexpr double kTol = 2e-3;
  std::size_t j = 0;
  for (const CanonMove* o : ma) {
    for (;;) {
      if (j >= mb.size()) return "ends early at original line " + std::to_string(o->line);
      const CanonMove& m = *mb[j++];
      if ((m.kind == CanonMove::Kind::Traverse) != (o->kind == CanonMove::Kind::Traverse))
        return "a rapid for a feed move at original line " + std::to_string(o->line);
      double off = 0.0;
      if (o->kind == CanonMove::Kind::Arc) {
        off = std::abs(std::hypot(m.x1 - o->xc, m.z1 - o->zc) - std::hypot(o->x0 - o->xc, o->z0 - o->zc));
      } else {
        const double lx = o->x1 - o->x0, lz = o->z1 - o->z0;
        off = std::abs(((m.x1 - o->x0) * lz - (m.z1 - o->z0) * lx) / std::hypot(lx, lz));
      }
      if (off > kTol) return "off the original path at line " + std::to_string(o->line);
      if (std::hypot(m.x1 - o->x1, m.z1 - o->z1) <= kTol) break;
      if (o->kind == CanonMove::Kind::Traverse) return "a split rapid at line " + std::to_string(o->line);
    }
  }
  return j == mb.size() ? "" : "moves beyond the original's end";
}

TEST(Acceptance, GeneratedProgramsKeepTheProgrammersInvariants) {
  if (!std::filesystem::exists("/usr/bin/rs274")) GTEST_SKIP() << "LinuxCNC's rs274 not installed";
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = systems::load_scenario(
      LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part_c45.toml", lib);
  const std::string tools = LATHECTL_SOURCE_DIR "/tests/optimize/programs/user_part_tools.toml";
  Options opt;
  opt.ini = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  opt.rs274 = "/usr/bin/rs274";
  opt.tool_specs = read_tool_file(io::read_input_file(tools, "a tool file", io::kMaxTomlBytes), tools);
  const std::string tbl = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.tbl";
  apply_tool_table(opt.tool_specs,
                   read_tool_table(io::read_input_file(tbl, "a tool table", io::kMaxTomlBytes), tbl),
                   tools, tbl);
  constexpr unsigned kPrograms = 100;
  int violations = 0, changed_lines = 0, plunges = 0, threads = 0, finishing = 0, cycles = 0,
      compensated = 0;
  double cycle0 = 0.0, cycle1 = 0.0;
  for (unsigned seed = 1; seed <= kPrograms; ++seed) {
    const auto g = testing::generate_program(seed);
    cycles += g.cycles ? 1 : 0;
    compensated += g.compensation ? 1 : 0;
    auto e = sc.get<systems::e_adaptive::Settings>();
    e.rig.stock.blank_diameter_mm = {{0.0, 2.0 * g.blank_radius_mm}, {80.0, 2.0 * g.blank_radius_mm}};
    Program p;
    p.file = "generated-" + std::to_string(seed) + ".ngc";
    p.lines = g.lines;
    p.canon = interpret(p.lines, p.file, opt);
    Result r;
    try {
      r = optimize(p, e, opt);
    } catch (const std::exception& ex) {
      ADD_FAILURE() << g.summary << ": " << ex.what();
      ++violations;
      continue;
    }
    const auto& moves = p.canon.moves;
    cycle0 += r.before.cycle_time_s;
    cycle1 += r.after.cycle_time_s;
    changed_lines += r.blocks_changed;
    // 1. the peak of the changed lines
    const auto& s = r.after.s;
    std::vector<double> f(s.param.size(), 0.0);
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto& m = moves[static_cast<std::size_t>(s.move[i])];
      const bool changed = m.line >= 1 && r.actions[static_cast<std::size_t>(m.line - 1)].changed;
      if (m.kind != CanonMove::Kind::Traverse && changed) f[i] = s.param[i];
    }
    const auto rev = control::per_revolution_mean(f, s.rpm, s.dt_s);
    for (std::size_t i = 0; i < rev.size(); ++i)
      if (rev[i] > e.rig.controller.load_limit) {
        ADD_FAILURE() << g.summary << ": line " << moves[static_cast<std::size_t>(s.move[i])].line
                      << " predicted " << rev[i] << " N per revolution, limit "
                      << e.rig.controller.load_limit;
        ++violations;
        break;
      }
    // 2. finishing never faster than written; 4. plunges within the insert's range
    for (std::size_t mi = 0; mi < moves.size(); ++mi) {
      const int line = moves[mi].line;
      const bool fin = std::find(g.finishing_lines.begin(), g.finishing_lines.end(), line) !=
                       g.finishing_lines.end();
      const bool plunge =
          std::find(g.plunge_lines.begin(), g.plunge_lines.end(), line) != g.plunge_lines.end();
      for (const auto& pc : r.optimized[mi]) {
        if (fin && pc.feed > moves[mi].feed * (1.0 + 1e-9)) {
          ADD_FAILURE() << g.summary << ": finishing line " << line << " fed " << pc.feed
                        << " for " << moves[mi].feed << " (" << pc.limited_by << ")";
          ++violations;
        }
        // G94: mm/min over the rpm (G97 only: the generator's G94 programs hold a speed)
        const double per_rev =
            moves[mi].per_rev ? pc.feed : pc.feed / spindle_rpm(moves[mi], moves[mi].x0);
        if (plunge && (per_rev < 0.02 * (1.0 - 1e-6) || per_rev > 0.08 * (1.0 + 1e-6)) &&
            pc.feed != moves[mi].feed) {
          ADD_FAILURE() << g.summary << ": plunge line " << line << " fed " << pc.feed;
          ++violations;
        }
      }
      finishing += fin ? 1 : 0;
      plunges += plunge ? 1 : 0;
    }
    // 3. thread lines as written
    std::vector<std::string> out;
    std::istringstream in(r.ngc);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    for (int tl : g.thread_lines) {
      ++threads;
      if (std::find(out.begin(), out.end(), g.lines[static_cast<std::size_t>(tl - 1)]) == out.end()) {
        ADD_FAILURE() << g.summary << ": thread line " << tl << " changed";
        ++violations;
      }
    }
    // 5. the path
    const auto again = interpret(out, p.file + " (optimised)", opt);
    const std::string diff = path_difference(p.canon, again);
    if (!diff.empty()) {
      ADD_FAILURE() << g.summary << ": the optimised program " << diff;
      ++violations;
    }
  }
  EXPECT_EQ(violations, 0);
  RecordProperty("programs", static_cast<int>(kPrograms));
  std::printf("acceptance: %u programs (%d roughed by G71 and finished by G70, %d finished under "
              "G42), %d violations, %d lines changed, %d finishing-line moves, %d plunge moves, "
              "%d threads; predicted cycles %.1f s -> %.1f s\n",
              kPrograms, cycles, compensated, violations, changed_lines, finishing, plunges,
              threads, cycle0, cycle1);
  // The kinds the generator promises are there in numbers.
  EXPECT_GE(cycles, 15);
  EXPECT_GE(compensated, 15);
}

}  // namespace
}  // namespace lathectl::optimize
