// The hand-written loops of bench/hand_loops.hpp against the rigs they copy: every recorded value
// and the final state bit for bit (the benchmarks' rig/hand ratio compares the same work).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>

#include "hand_loops.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

using namespace lathectl;

namespace {
io::Scenario load(const char* name) {
  static const auto lib = io::MaterialLibrary::load_default();
  return systems::load_scenario(std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/") + name,
                                lib);
}
std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

void expect_rows(const sim::Recorder& rec, const bench::HandRun& h) {
  ASSERT_EQ(h.channels, rec.channels().size());
  ASSERT_EQ(h.rows, rec.rows());
  for (std::size_t c = 0; c < h.channels; ++c) {
    const auto col = rec.column(c);
    for (std::size_t r = 0; r < h.rows; ++r)
      ASSERT_EQ(bits(col[r]), bits(h.at(r, c)))
          << rec.channels()[c].name << " row " << r << ": " << col[r] << " vs " << h.at(r, c);
  }
}

// Rig A over the scenario's whole run (the allowance's step at 4 mm included).
void expect_rig_a(const char* scenario) {
  const auto sc = load(scenario);
  const auto& cfg = sc.get<systems::a_pulse_feed::Settings>().rig;
  systems::a_pulse_feed::Rig rig;
  rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  rig.run();
  const auto h =
      bench::hand_loop_a(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  ASSERT_GT(h.rows, 5000u);
  expect_rows(rig.recorder(), h);
  EXPECT_EQ(bits(rig.time()), bits(h.t_s));
  EXPECT_EQ(bits(rig.position()), bits(h.x));
  EXPECT_EQ(bits(rig.force()), bits(h.force_N));
  EXPECT_EQ(bits(rig.tool_life_used()), bits(h.life_used));
  EXPECT_EQ(bits(rig.tool_life_used_after_disturbance()), bits(h.life_used_td));
  EXPECT_EQ(bits(rig.first_disturbance_time()), bits(h.t_disturbance_s));
  EXPECT_GT(h.t_disturbance_s, 0.0);
  const auto vb = rig.volume_balance();
  EXPECT_EQ(bits(vb.delivered_m3), bits(h.delivered_m3));
  EXPECT_EQ(bits(vb.leaked_m3), bits(h.leaked_m3));
  EXPECT_EQ(rig.numerically_sound(), h.sound);
}
}  // namespace

TEST(HandLoop, RigAUncontrolledBitIdentical) { expect_rig_a("a_finishing_none.toml"); }
TEST(HandLoop, RigAAimBitIdentical) { expect_rig_a("a_finishing_aim.toml"); }

// Rig B's feed division (the part chattering, the module measuring it): the idle block and 2 s
// of cut.
TEST(HandLoop, RigBFeedDivisionBitIdentical) {
  const auto sc = load("b_twin_feed_division.toml");
  auto b = sc.get<systems::b_chatter::Settings>().rig;
  b.z_end_mm = b.z_start_mm + b.feed_mm_per_rev * b.rpm / 60.0 * 2.0;
  systems::b_chatter::Rig rig;
  rig.configure(b, sc.run.step_s, sc.run.record_interval_s, 12.0);
  rig.run();
  const auto h = bench::hand_loop_b(b, sc.run.step_s, sc.run.record_interval_s, 12.0);
  ASSERT_GT(h.rows, 2000u);
  expect_rows(rig.recorder(), h);
  EXPECT_EQ(bits(rig.time_s()), bits(h.t_s));
  EXPECT_EQ(bits(rig.process().y_m()), bits(h.y_m));
  EXPECT_EQ(bits(rig.process().radial_N(0)), bits(h.force_N));
  EXPECT_EQ(rig.numerically_sound(), h.sound);
  const auto y = rig.recorder().column("y_um");
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  EXPECT_GT(*hi - *lo, 1.0) << *lo << " " << *hi;  // the part vibrates
}
