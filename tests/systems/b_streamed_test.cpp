// System B streamed: the rig records no columns; channels.csv is written as the rows
// come and the study's measures are taken row by row, the steady window's rows kept on disk
// (io::RowSpill) until the cut's end places the window. Both give what the columns record gives,
// bit for bit (the numbers themselves are held to the runs before streaming by golden_summaries).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/b_chatter/metrics.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl {
namespace {

namespace fs = std::filesystem;
using test::library;

fs::path scratch(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("lathectl-b-streamed-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  return d;
}

// Equal as bits (NaN equal to NaN).
void expect_same(double a, double b, const char* what) {
  if (std::isnan(a) && std::isnan(b)) return;
  EXPECT_EQ(a, b) << what;
}

TEST(RowSpill, GivesBackTheRowsBitForBitFromDiskAndMemory) {
  const fs::path dir = scratch("spill");
  io::OutputStage stage(dir);
  io::RowSpill disk(&stage, "rows", 3, 100.0, 7);  // blocks of 7 rows: 14 written, 2 in memory
  io::RowSpill memory(nullptr, "rows", 3, 100.0);
  for (int i = 0; i < 100; ++i) {
    const double row[3] = {0.1 * i, std::exp(-0.3 * i), i % 9 == 0 ? NAN : 1.0 / (i + 1)};
    disk.push(row);
    memory.push(row);
  }
  EXPECT_TRUE(disk.on_disk());
  EXPECT_FALSE(memory.on_disk());
  ASSERT_EQ(disk.rows(), 100u);
  for (std::size_t from : {0u, 5u, 6u, 7u, 55u, 97u, 99u}) {
    std::vector<double> a(3 * 11), b(3 * 11);
    const std::size_t n = disk.read(from, a);
    ASSERT_EQ(n, std::min<std::size_t>(11, 100 - from));
    ASSERT_EQ(memory.read(from, b), n);
    for (std::size_t k = 0; k < 3 * n; ++k) expect_same(a[k], b[k], "value");
    EXPECT_EQ(a[0], 0.1 * static_cast<double>(from));
  }
  std::vector<double> none(3);
  EXPECT_EQ(disk.read(100, none), 0u);
  // The spill's file has no name: nothing but the stage's marker is left in the stage.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(stage.path()))
    files += e.path().filename() != ".lathectl-output";
  EXPECT_EQ(files, 0u);
}

TEST(SystemBStreamed, ChannelsAndMeasuresEqualTheColumnsRecord) {
  // The example's twin turrets with the automatic module, over 4 mm of the cut (about 2.6 s).
  const auto sc =
      systems::parse_scenario(test::example_text("b_twin_feed_division"), "mem.toml", library());
  systems::b_chatter::RigConfig b = sc.get<systems::b_chatter::Settings>().rig;
  b.z_end_mm = b.z_start_mm + 4.0;
  const double dead_zone_um = b.vibration.dead_zone_m * 1e6;

  systems::b_chatter::Run cols;  // columns, measured by replaying its rows
  cols.rig.configure(b, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  cols.rig.run();
  cols.measure = std::make_unique<systems::b_chatter::Measure>(cols.rig, true, nullptr);
  cols.rig.recorder().replay(*cols.measure);
  cols.measure->result(cols, dead_zone_um);

  const fs::path dir = scratch("set");
  io::OutputStage stage(dir);
  systems::b_chatter::Run st;  // streamed: channels.csv and the window's rows into the stage
  st.rig.set_streamed(true);
  st.rig.configure(b, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  st.measure = std::make_unique<systems::b_chatter::Measure>(st.rig, true, &stage, 100);
  st.csv = io::open_channel_stream(&stage, "channels.csv", st.rig.recorder().channels(),
                                   st.rig.max_record_rows());
  st.rig.attach(st.measure.get());
  st.rig.attach(st.csv.get());
  st.rig.run();
  st.csv->finish();
  st.measure->result(st, dead_zone_um);

  ASSERT_GT(cols.rig.recorder().rows(), 2000u);  // the window's rows span many spill blocks
  EXPECT_EQ(st.rig.recorder().rows(), cols.rig.recorder().rows());
  std::ifstream in(stage.path() / "channels.csv", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(text.str() == io::channels_csv(cols.rig.recorder())) << "channels.csv differs";

  EXPECT_GT(cols.vibration_um, 0.0);
  expect_same(st.vibration_um, cols.vibration_um, "vibration");
  expect_same(st.forced_um, cols.forced_um, "forced");
  expect_same(st.static_um, cols.static_um, "static");
  expect_same(st.chatter_Hz, cols.chatter_Hz, "chatter frequency");
  expect_same(st.feed_mean[0], cols.feed_mean[0], "feed right");
  expect_same(st.feed_mean[1], cols.feed_mean[1], "feed left");
  expect_same(st.cut_power_W, cols.cut_power_W, "power");
  expect_same(st.cut_power_measured_W, cols.cut_power_measured_W, "power measured");
  expect_same(st.one_out_share, cols.one_out_share, "one out");
  expect_same(st.delay_min_rev, cols.delay_min_rev, "delay min");
  expect_same(st.delay_max_rev, cols.delay_max_rev, "delay max");
  expect_same(st.t0, cols.t0, "t0");
  expect_same(st.t1, cols.t1, "t1");
  expect_same(st.t_end, cols.t_end, "t_end");
  EXPECT_GT(cols.surface.length_mm, 0.0);
  expect_same(st.surface.length_mm, cols.surface.length_mm, "surface length");
  expect_same(st.surface.Rz_mean_um, cols.surface.Rz_mean_um, "Rz mean");
  expect_same(st.surface.Rz_min_um, cols.surface.Rz_min_um, "Rz min");
  expect_same(st.surface.Rz_max_um, cols.surface.Rz_max_um, "Rz max");
  expect_same(st.surface.Ra_mean_um, cols.surface.Ra_mean_um, "Ra mean");
  fs::remove_all(dir.parent_path());
}

}  // namespace
}  // namespace lathectl
