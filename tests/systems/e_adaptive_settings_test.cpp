// System E's section reader (src/systems/e_adaptive/settings.cpp): every key described, and the
// defaults of a scenario that gives only the required keys are the ones the old reader used
// (where a library struct's own default differs, E's settings carry E's value).

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::systems::e_adaptive {
namespace {

using lathectl::test::library;

constexpr const char* kMinimal = R"(system = "E"
name = "minimal"
[run]
duration_s = 10.0
[material]
name = "steel_45"
[stock]
blank = [ { at_mm = 0.0, diameter_mm = 60.0 } ]
passes = [ { z_start_mm = 0.0, z_end_mm = 20.0, diameter_mm = 56.0 } ]
[feed_axis]
[spindle]
inertia_kg_m2 = 0.5
max_torque_N_m = 400.0
max_power_kW = 15.0
[sensor]
parameter = "Pz"
[controller]
type = "force_speed"
force_limit_N = 1500.0
feed_mm_per_rev = 0.3
speed_m_per_min = 150.0
planned_depth_mm = 2.0
)";

TEST(ESettings, EveryKeyIsDescribed) {
  for (const io::Section* s : {&kReadSection, &kSection}) {
    const auto log = io::describe_section(*s, library());
    std::set<std::string> keys;
    for (const auto& r : log) {
      keys.insert(r.key);
      if (r.kind == "table" || r.kind == "array of tables") continue;
      // The common tables (sections.cpp: [material], [tool], [[fault]]) are not E's to describe.
      if (r.key.starts_with("material.") || r.key.starts_with("tool.") ||
          r.key.starts_with("fault[]."))
        continue;
      EXPECT_FALSE(r.doc.empty()) << r.key;
    }
    for (const char* k : {"stock.blank[].diameter_mm", "stock.passes[].z_end_mm",
                          "feed_axis.velocity_window_ms", "sensor.noise_N", "sensor.noise_W",
                          "controller.force_limit_N", "controller.cut_power_limit_kW",
                          "controller.sensor_stuck_ms", "compare.controllers"})
      EXPECT_TRUE(keys.count(k)) << k;
  }
}

// The old reader's defaults, now the settings' own (docs/scenario-reference.md's "Known
// inconsistencies" for E are gone).
TEST(ESettings, DefaultsAreTheScenarioReadersOfOld) {
  const auto sc = io::parse_scenario(kMinimal, "minimal.toml", library(), kSection);
  const auto& e = sc.get<Settings>().rig;
  EXPECT_EQ(e.controller.feed_max_mm_per_rev, 0.8);            // Params had 0.6
  EXPECT_EQ(e.controller.speed_rate_limit_m_per_min_per_s, 100.0);  // Params had 200
  EXPECT_EQ(e.axis.velocity_window_s, 0.02);                   // FeedAxis: 0.01
  EXPECT_EQ(e.spindle.idle_p0_W, 0.0);                         // SpindleDrive: 300 W …
  EXPECT_EQ(e.spindle.idle_p1_W_per_rpm, 0.0);
  EXPECT_EQ(e.spindle.idle_p2_W_per_rpm2, 0.0);
  EXPECT_EQ(e.disturbances.random_correlation_mm, 20.0);       // DisturbanceParams: 5
  EXPECT_EQ(e.force_sensor.range, 1e5);                        // LaggedNoisySensor: 1e9
  EXPECT_EQ(e.power_meter.time_constant_s, 0.02);              // LaggedNoisySensor: 0.002
  EXPECT_EQ(e.power_meter.range, 1e9);
  EXPECT_EQ(e.controller.sensor_monitor.stuck_time_s, 0.1);    // SignalMonitor: 0 (off)
  // Defaults derived from other keys.
  EXPECT_EQ(e.controller.air_feed_mm_per_rev, 0.3);
  EXPECT_EQ(e.controller.feed_planned_mm_per_rev, 0.3);
  EXPECT_EQ(e.controller.entry_feed_mm_per_rev, 0.05);
  EXPECT_EQ(e.controller.sensor_monitor.min, -0.2 * 1500.0);
  EXPECT_EQ(e.controller.sensor_monitor.max, 1e5);
  EXPECT_DOUBLE_EQ(e.controller.cut_power_max_W, 0.9 * 15000.0 * 0.85);
  EXPECT_EQ(e.controller.rpm_max, e.spindle.max_rpm);
  EXPECT_TRUE(sc.get<Settings>().compare_modes.empty());
}

TEST(ESettings, PowerSensorReadsItsKeysInWatts) {
  std::string text = kMinimal;
  text.replace(text.find(R"(parameter = "Pz")"), 16, "parameter = \"power\"\nrange_W = 9000.0");
  text.replace(text.find("force_limit_N = 1500.0"), 22, "cut_power_limit_kW = 4.5");
  const auto sc = io::parse_scenario(text, "power.toml", library(), kReadSection);
  const auto& e = sc.get<Settings>().rig;
  EXPECT_EQ(e.force_parameter, cutting::ForceParameter::Power);
  EXPECT_EQ(e.controller.load_limit, 4500.0);
  EXPECT_EQ(e.force_sensor.range, 9000.0);
  // A force key with a power sensor is unknown.
  text.replace(text.find("range_W"), 7, "range_N");
  EXPECT_THROW(io::parse_scenario(text, "power.toml", library(), kReadSection), io::InputError);
}

// A key added to the reader in one line (what the one-description-per-key reader is for): the
// controller averages the force over a revolution unless the scenario says otherwise.
TEST(ESettings, AveragePerRevolutionIsAScenarioKey) {
  EXPECT_TRUE(io::parse_scenario(kMinimal, "m.toml", library(), kReadSection)
                  .get<Settings>()
                  .rig.controller.average_per_revolution);
  std::string text = kMinimal;
  text.replace(text.find("planned_depth_mm = 2.0"), 22,
               "planned_depth_mm = 2.0\naverage_per_revolution = false");
  EXPECT_FALSE(io::parse_scenario(text, "m.toml", library(), kReadSection)
                   .get<Settings>()
                   .rig.controller.average_per_revolution);
}

}  // namespace
}  // namespace lathectl::systems::e_adaptive
