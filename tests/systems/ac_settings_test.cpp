// Systems A and C's section readers (src/systems/a_pulse_feed, src/systems/c_tracer): described
// keys (the reference they generate), one default per key whether or not its table is written,
// and the read-only section that skips the rig probe.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/c_tracer/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl {
namespace {

using test::edited;
using test::library;
std::string example(const std::string& name) { return test::example_text(name); }

// The shared tables (io/sections.cpp) and the common part are described elsewhere.
bool shared_key(const std::string& key) {
  for (const char* p : {"system", "name", "description", "run", "material", "tool", "fault"})
    if (key == p || key.rfind(std::string(p) + ".", 0) == 0 ||
        key.rfind(std::string(p) + "[", 0) == 0)
      return true;
  return false;
}

const io::ParamRecord* row(const io::ParamLog& log, const std::string& key) {
  for (const auto& r : log)
    if (r.key == key) return &r;
  return nullptr;
}

TEST(SystemASettings, EveryKeyIsDescribed) {
  io::ParamLog log;
  ASSERT_NO_THROW(log = io::describe_section(systems::a_pulse_feed::kSection, library()));
  for (const auto& r : log) {
    if (!shared_key(r.key)) {
      EXPECT_FALSE(r.doc.empty()) << r.key;
    }
  }
  // Keys read only in some cases are listed too, with the defaults the settings carry.
  for (const char* k : {"controller.force_set_N", "eccentric.profile", "eccentric.eccentricity_mm",
                        "compare.controller", "compare.regulator", "sweep.leak_estimate_factor",
                        "part.depth_steps[].at_mm", "regulator.obliteration.critical_gap_um",
                        "metrics.feed_window_s"})
    EXPECT_NE(row(log, k), nullptr) << k;
  const auto* ff = row(log, "controller.force_filter_ms");
  ASSERT_NE(ff, nullptr);
  EXPECT_EQ(ff->fallback, "5");
  const auto* ms = row(log, "eccentric.motor_max_speed_rpm");
  ASSERT_NE(ms, nullptr);
  EXPECT_EQ(ms->fallback, "3000");
  // A cross-field rule the defaults break is listed beside its key.
  EXPECT_NE(row(log, "compare.controller")->rules.find("give controller and/or regulator"),
            std::string::npos);
}

TEST(SystemASettings, EccentricDefaultsAreTheSameWithoutTheTable) {
  // One default per key: no [eccentric] now means what an [eccentric] without keys means (before
  // one default per key the motor's limit was 300 rad/s without the table and 3000 rpm with
  // it).
  const std::string text = example("a_finishing_aim");
  const std::string without = edited(
      text,
      "[eccentric]\neccentricity_mm = 0.05\ngear_ratio = 200.0\nmotor_max_speed_rpm = 3000.0\n"
      "motor_time_constant_ms = 20.0\nposition_gain_per_s = 30.0\n",
      "");
  const auto sc = systems::parse_scenario(without, "mem.toml", library());
  const auto& e = sc.get<systems::a_pulse_feed::Settings>().rig.eccentric;
  EXPECT_DOUBLE_EQ(e.motor_max_speed_rad_per_s, 3000.0 * 2.0 * std::numbers::pi / 60.0);
  EXPECT_DOUBLE_EQ(e.gear_ratio, 100.0);
  const auto empty = systems::parse_scenario(
      edited(without, "[slide]\n", "[eccentric]\n\n[slide]\n"), "mem.toml", library());
  const auto& e2 = empty.get<systems::a_pulse_feed::Settings>().rig.eccentric;
  EXPECT_EQ(e2.motor_max_speed_rad_per_s, e.motor_max_speed_rad_per_s);
  EXPECT_EQ(e2.motor_time_constant_s, e.motor_time_constant_s);
  EXPECT_EQ(e2.position_gain_per_s, e.position_gain_per_s);
}

TEST(SystemASettings, ReadSectionSkipsTheRigProbe) {
  // A step far too coarse for the hydraulics: the rig rejects it, the reader alone does not.
  const std::string coarse =
      edited(example("a_finishing_aim"), "step_s = 1e-4\nrecord_interval_s = 2e-3",
             "step_s = 5e-3\nrecord_interval_s = 1e-2");
  EXPECT_THROW(io::parse_scenario(coarse, "mem.toml", library(), systems::a_pulse_feed::kSection),
               io::InputError);
  const auto sc =
      io::parse_scenario(coarse, "mem.toml", library(), systems::a_pulse_feed::kReadSection);
  EXPECT_DOUBLE_EQ(sc.run.step_s, 5e-3);
  EXPECT_TRUE(sc.get<systems::a_pulse_feed::Settings>().compare.has_value());
}

TEST(SystemCSettings, EveryKeyIsDescribed) {
  io::ParamLog log;
  ASSERT_NO_THROW(log = io::describe_section(systems::c_tracer::kSection, library()));
  for (const auto& r : log) {
    if (!shared_key(r.key)) {
      EXPECT_FALSE(r.doc.empty()) << r.key;
    }
  }
  for (const char* k : {"template.csv", "template.features[].type", "template.features[].angle_deg",
                        "template.features[].radius_mm", "template.features[].height_mm",
                        "model.compare", "servo.clearance_leak_cm3_per_min_per_MPa",
                        "friction.static_N", "cutting.blank_diameter_mm"})
    EXPECT_NE(row(log, k), nullptr) << k;
  const auto* coulomb = row(log, "friction.coulomb_N");
  ASSERT_NE(coulomb, nullptr);
  EXPECT_EQ(coulomb->fallback, "0");
}

TEST(SystemCSettings, FrictionDefaultsAreTheSameWithoutTheTable) {
  // Before one default per key, no [friction] meant 200 N Coulomb and static, 2000 N·s/m
  // viscous, and an empty [friction] zeros: now both are the reader's zeros.
  const std::string text = example("c_dead_zone");
  const auto pos = text.find("[friction]");
  ASSERT_NE(pos, std::string::npos);
  const auto next = text.find("\n[", pos + 1);
  const std::string without =
      text.substr(0, pos) + (next == std::string::npos ? "" : text.substr(next + 1));
  const auto sc = systems::parse_scenario(without, "mem.toml", library());
  const auto& c = sc.get<systems::c_tracer::Settings>().rig;
  const std::string empty_table = text.substr(0, pos) + "[friction]\n" +
                                  (next == std::string::npos ? "" : text.substr(next + 1));
  const auto sc2 = systems::parse_scenario(empty_table, "mem.toml", library());
  const auto& c2 = sc2.get<systems::c_tracer::Settings>().rig;
  EXPECT_EQ(c.coulomb_N, 0.0);
  EXPECT_EQ(c.static_N, 0.0);
  EXPECT_EQ(c.viscous_N_s_per_m, 0.0);
  EXPECT_EQ(c2.coulomb_N, c.coulomb_N);
  EXPECT_EQ(c2.static_N, c.static_N);
  EXPECT_EQ(c2.stribeck_velocity_m_per_s, c.stribeck_velocity_m_per_s);
  EXPECT_EQ(c2.viscous_N_s_per_m, c.viscous_N_s_per_m);
}

TEST(SystemCSettings, OptionalCompareIsEmptyWhenAbsent) {
  const auto sc = systems::parse_scenario(example("c_stepped_tapered_slow"), "mem.toml", library());
  EXPECT_EQ(sc.get<systems::c_tracer::Settings>().compare, "");
  const auto sc2 = systems::parse_scenario(example("c_dead_zone"), "mem.toml", library());
  EXPECT_EQ(sc2.get<systems::c_tracer::Settings>().compare, "linear");
}

}  // namespace
}  // namespace lathectl
