// bench/hand_loop_e.hpp, rig E's cutting process written out by hand for BM_HandLoopE, gives the
// rig's plant's numbers bit for bit on the rig's own tool path over a whole part.

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>

#include "../../bench/hand_loop_e.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"

using namespace lathectl::systems;

namespace {
bool same(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
}  // namespace

// Rig E over e_stepped_seed004's part (its [tool] changed by `tool`, at most `max_steps`) against
// the hand copy, step by step, bit for bit; the steps and those in contact, counted.
struct Compared {
  std::size_t steps = 0, in_cut = 0;
  bool finished = false;
};
template <class Tool>
Compared compare_over_part(Tool tool, std::size_t max_steps) {
  const auto sc = lathectl::io::load_scenario(
      std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/e_stepped_seed004.toml"),
      lathectl::test::library(), e_adaptive::kReadSection);
  auto cfg = sc.get<e_adaptive::Settings>().rig;
  tool(cfg);
  e_adaptive::Rig rig;
  rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  auto process = e_adaptive::lathe_process(cfg);
  process.faults.clear();
  lathectl::bench::HandCutE hand;
  hand.configure(process);
  lathectl::bench::HandCutE::Out h;
  Compared c;
  while (c.steps < max_steps && rig.step()) {
    const auto& in = rig.cut_input();
    const auto& p = rig.cut_output();
    hand.step(in.x_mm, in.z_mm, in.rpm, sc.run.step_s, h);
    const bool ok = same(h.Pz, p.Pz_N) && same(h.Py, p.Py_N) && same(h.depth, p.depth_mm) &&
                    same(h.feed, p.feed_per_rev_mm) && same(h.removed_mm3, p.removed_mm3) &&
                    same(h.force_measured, p.force_measured);
    EXPECT_TRUE(ok) << "step " << c.steps << ": Pz " << h.Pz << " vs " << p.Pz_N;
    if (!ok) break;
    ++c.steps;
    c.in_cut += p.in_contact ? 1 : 0;
  }
  c.finished = rig.finished();
  return c;
}

TEST(HandLoopE, TheRigsPlantBitForBitOverAPart) {
  const Compared c = compare_over_part([](e_adaptive::RigConfig&) {}, SIZE_MAX);
  EXPECT_TRUE(c.finished);
  EXPECT_GT(c.in_cut, c.steps / 2);  // mostly cutting: the comparison covers the cut
}

// The same with the insert's straight edges (a CNMG in a 95° holder, I85 J5 at Q2): the hand
// copy cuts along them as the plant does, bit for bit.
TEST(HandLoopE, TheRigsPlantBitForBitWithTheInsertsEdges) {
  const Compared c = compare_over_part(
      [](e_adaptive::RigConfig& cfg) {
        cfg.tool_front_angle_deg = 85.0;
        cfg.tool_back_angle_deg = 5.0;
      },
      200000);
  EXPECT_GT(c.in_cut, c.steps / 2);
}
