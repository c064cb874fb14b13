// Rig E's machine-side stock model takes the plant's cut (LathePlant::follow): over example parts
// every recorded row, bit for bit, is what it is when the model cuts its own grid, and the
// model followed the plant at every step (the same tool position each step: no own cut needed).

#include <gtest/gtest.h>

#include <cstring>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"

using namespace lathectl::systems;

namespace {

struct Rows : lathectl::sim::RowSink {
  std::vector<double> values;
  void row(std::span<const double> v) noexcept override {
    values.insert(values.end(), v.begin(), v.end());
  }
};

struct Part {
  Rows rows;
  double cycle = 0.0, life = 0.0, removed = 0.0;
  bool followed = false;
};

void run(const lathectl::io::Scenario& sc, double duration_s, bool share, Part& out) {
  e_adaptive::Rig rig;
  rig.share_cut(share);
  rig.configure(sc.get<e_adaptive::Settings>().rig, sc.run.step_s, sc.run.record_interval_s,
                duration_s);
  rig.attach(&out.rows);
  rig.run();
  out.cycle = rig.cycle_time_s();
  out.life = rig.tool_life_used();
  out.removed = rig.material_removed_cm3();
  out.followed = rig.machine().stock_following();
}

}  // namespace

TEST(RigEShareCut, SameRowsBitForBitAsTheModelsOwnCut) {
  // seed 004's whole part; the tool-life law (it reads the model's chip) over its first 40 s.
  for (const auto& [name, duration] : {std::pair{"e_stepped_seed004.toml", 1e9},
                                       std::pair{"e_stepped_life.toml", 40.0}}) {
    SCOPED_TRACE(name);
    const auto sc = lathectl::io::load_scenario(
        std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/") + name, lathectl::test::library(),
        e_adaptive::kReadSection);
    Part own, shared;
    run(sc, duration, false, own);
    run(sc, duration, true, shared);
    EXPECT_FALSE(own.followed);
    EXPECT_TRUE(shared.followed);  // in step with the plant over the whole part
    ASSERT_GT(own.rows.values.size(), 1000u);
    ASSERT_EQ(own.rows.values.size(), shared.rows.values.size());
    EXPECT_EQ(0, std::memcmp(own.rows.values.data(), shared.rows.values.data(),
                             own.rows.values.size() * sizeof(double)));
    EXPECT_EQ(own.cycle, shared.cycle);
    EXPECT_EQ(own.life, shared.life);
    EXPECT_EQ(own.removed, shared.removed);
  }
}
