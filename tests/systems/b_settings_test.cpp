// System B's section reader (src/systems/b_chatter/settings.cpp): the keys beyond the seed — the
// reading of the seed formula's 1.41, the inter-tool delay of depth division and the process
// damping — with their defaults, what each choice sets, and a bad value refused.

#include <gtest/gtest.h>

#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl {
namespace {

using test::edited;
using test::library;

const systems::b_chatter::RigConfig& rig(const io::Scenario& sc) {
  return sc.get<systems::b_chatter::Settings>().rig;
}

TEST(SystemBSettings, DefaultsKeepTheModelOfTheGoldenRuns) {
  const auto sc =
      systems::parse_scenario(test::example_text("b_twin_depth_division"), "mem.toml", library());
  const auto& b = rig(sc);
  EXPECT_FALSE(b.seed_divides);
  EXPECT_DOUBLE_EQ(b.seed_coefficient, 1.41);
  EXPECT_DOUBLE_EQ(b.module.coefficient, 1.41);
  EXPECT_EQ(b.inter_tool_delay, dynamics::InterToolDelay::AxialPositions);
  EXPECT_FALSE(b.process_damping.on());
}

TEST(SystemBSettings, EachChoiceSetsWhatItSays) {
  std::string text = test::example_text("b_twin_depth_division");
  text = edited(text, "coefficient = 1.41\n",
                "coefficient = 1.41\ncoefficient_reading = \"divide\"\n");
  text = edited(text, "tool2_lag_mm = 2.0\n", "tool2_lag_mm = 2.0\ninter_tool_delay = \"fixed\"\n");
  text += "\n[process_damping]\nmodel = \"indentation\"\nK_sp_N_per_mm3 = 2e4\nwear_land_mm = 0.05\n";
  const auto sc = systems::parse_scenario(text, "mem.toml", library());
  const auto& b = rig(sc);
  EXPECT_TRUE(b.seed_divides);
  EXPECT_NEAR(b.module.coefficient, 1.0 / 1.41, 1e-15);  // B ≥ a0/√2 with the printed 1.41
  EXPECT_EQ(b.inter_tool_delay, dynamics::InterToolDelay::Fixed);
  EXPECT_TRUE(b.process_damping.on());
  EXPECT_DOUBLE_EQ(b.process_damping.k_sp_N_per_m3, 2e13);
  EXPECT_DOUBLE_EQ(b.process_damping.wear_land_mm, 0.05);
}

TEST(SystemBSettings, RefusesAnUnknownReading) {
  const std::string text = edited(test::example_text("b_twin_feed_division"), "coefficient = 1.41\n",
                                  "coefficient = 1.41\ncoefficient_reading = \"half\"\n");
  EXPECT_THROW(systems::parse_scenario(text, "mem.toml", library()), io::InputError);
}

}  // namespace
}  // namespace lathectl
