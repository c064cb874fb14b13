// One description per system: a machine's parameters are derived from a scenario in one place
// (systems::<folder>::machine_params), and every host — the rig `lathectl run` runs, the LinuxCNC
// component with the sample configuration's module parameters, `lathectl optimize`'s prediction —
// runs exactly those, field by field, on every example scenario. Before this test the hosts built
// them by hand and differed (E: the optimiser without the feed-forward setting, the tool-life law,
// inertia learning, the power sensor and its lag; the component without the air-feed floor and
// with the power meter's lag 0; D: the component's own arming and guard).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "lathectl/io/scenario.hpp"
#include "optimize/adaptive_params.hpp"
#include "optimize/optimize.hpp"
#include "support/library.hpp"
#include "systems/d_gauging/machine_params.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::systems {
namespace {

namespace fs = std::filesystem;
using lathectl::test::library;

// Every example scenario of a system (the scenarios and the LinuxCNC configurations' own), read
// as a HAL component reads it (the system's section alone, no cross-checks), once per test binary.
const std::vector<io::Scenario>& examples(const io::Section& section) {
  static std::map<std::string, std::vector<io::Scenario>> cache;
  const std::string system(section.system);
  auto [it, added] = cache.try_emplace(system);
  if (!added) return it->second;
  const std::regex line("^system\\s*=\\s*\"" + system + "\"");
  for (const char* dir : {"/examples/scenarios", "/examples/linuxcnc"}) {
    for (const auto& f : fs::directory_iterator(std::string(LATHECTL_SOURCE_DIR) + dir)) {
      if (f.path().extension() != ".toml") continue;
      std::ifstream in(f.path());
      bool ours = false;
      for (std::string l; !ours && std::getline(in, l);) ours = std::regex_search(l, line);
      if (ours)
        it->second.push_back(io::load_scenario(f.path().string(), library(), section));
    }
  }
  return it->second;
}

TEST(MachineParams, EveryHostOfSystemERunsTheScenariosMachine) {
  const auto& scenarios = examples(e_adaptive::kReadSection);
  ASSERT_GE(scenarios.size(), 12u);
  for (const auto& sc : scenarios) {
    SCOPED_TRACE(sc.file);
    const auto& e = sc.get<e_adaptive::Settings>();
    // The rig as `lathectl run` configures it (z = 0 at the stock's face).
    e_adaptive::Rig rig;
    rig.configure(e.rig, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
    const auto& ran = rig.machine().params();
    // lathectl_adaptive as the sample configuration loads it: sensor=force, z_origin_mm=0.
    const auto hal = e_adaptive::machine_params(e.rig, {.z_origin_mm = 0.0});
    // `lathectl optimize` with linuxcnc-sim's z origin.
    optimize::Options opt;
    opt.z_origin_mm = 0.0;
    const auto optimiser = optimize::adaptive_machine_params(e, opt);
    auto expect = hal;
    if (e.rig.force_parameter == cutting::ForceParameter::Power)  // (e_forged_shaft_power)
      // lathectl_adaptive with sensor=power: sensor 4 is the drive's power meter, as in the rig
      expect = e_adaptive::machine_params(
          e.rig, {.load = e_adaptive::MachineHost::Load::SpindlePower, .z_origin_mm = 0.0});
    if (e.rig.worst_case_feed) {  // the rig writes its own program: the worst case's feed
      expect.controller.feed_programmed_mm_per_rev = ran.controller.feed_programmed_mm_per_rev;
      expect.controller.feed_min_mm_per_rev = ran.controller.feed_min_mm_per_rev;
    }
    EXPECT_TRUE(ran == expect) << "the rig runs another machine than lathectl_adaptive";
    EXPECT_TRUE(optimiser == hal) << "optimize predicts another machine than lathectl_adaptive";
    // Field by field where the hosts differed before.
    EXPECT_EQ(optimiser.feed_forward, e.rig.feed_forward);
    EXPECT_EQ(optimiser.life_law, e.rig.life_law);
    EXPECT_EQ(optimiser.learn_inertia, e.rig.learn_inertia);
    // Sensor 4 on the force input for both (the plant's sensor 4); the rig's power parameter is
    // the drive's meter (MachineHost::Load::SpindlePower), which lathectl_adaptive runs with
    // sensor=power.
    EXPECT_FALSE(optimiser.power_sensor);
    EXPECT_EQ(hal.power_lag_s, ran.power_lag_s);
    EXPECT_GT(hal.controller.air_feed_mm_per_rev, 0.0);
    EXPECT_TRUE(hal.controller == ran.controller || e.rig.worst_case_feed);
    EXPECT_TRUE(hal.process == ran.process);
  }
}

TEST(MachineParams, SystemEOnTheSpindlesPowerIsThePowerSensorsMachine) {
  // A dynamometer's scenario on a machine that reads the drive's power (sensor=power): the load,
  // its range and its limit in W; the scenario's own power scenario keeps its [controller].
  for (const auto& sc : examples(e_adaptive::kReadSection)) {
    SCOPED_TRACE(sc.file);
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    const auto p = e_adaptive::machine_params(
        e, {.load = e_adaptive::MachineHost::Load::SpindlePower, .z_origin_mm = 0.0});
    EXPECT_TRUE(p.power_sensor);
    EXPECT_STREQ(e_adaptive::load_unit(e, {.load = e_adaptive::MachineHost::Load::SpindlePower}),
                 "W");
    EXPECT_EQ(p.rating.limit_max, e.spindle.max_power_W);
    if (e.force_parameter == cutting::ForceParameter::Power) {
      EXPECT_TRUE(p.controller == e_adaptive::machine_params(e, {}).controller);
    } else {
      EXPECT_EQ(p.controller.load_limit,
                std::min(e.controller.cut_power_max_W, e.spindle.max_power_W));
      EXPECT_EQ(p.controller.sensor_monitor.min, -1.2 * e.spindle.max_power_W);
      EXPECT_EQ(p.controller.sensor_monitor.max, 2.0 * e.spindle.max_power_W);
    }
  }
}

TEST(MachineParams, SystemEToolLifeLawNeedsTheStockModel) {
  for (const auto& sc : examples(e_adaptive::kReadSection)) {
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    if (!e.life_law) continue;
    EXPECT_THROW((void)e_adaptive::machine_params(e, {.z_origin_mm = std::nan("")}),
                 std::invalid_argument)
        << sc.file;
  }
}

TEST(MachineParams, EveryHostOfSystemDRunsTheScenariosGauge) {
  const auto& scenarios = examples(d_gauging::kReadSection);
  ASSERT_GE(scenarios.size(), 5u);
  for (const auto& sc : scenarios) {
    SCOPED_TRACE(sc.file);
    const auto& d = sc.get<d_gauging::Settings>();
    sensors::VibroContactGauge g;
    d_gauging::configure_transducer(sc, g);
    const auto plan = d_gauging::plan_threshold(d, sc.run.step_s);
    auto p = d.process;
    d_gauging::Sequence seq = d.sequence;
    seq.enabled = true;  // the machine's cycle (lathectl_gauge always roughs and fines)
    p.cycle = d_gauging::cycle_for(d.transducer, seq, plan.line, p, plan.threshold_V);
    const auto rig = d_gauging::machine_params(p, g, plan.threshold_V);
    // lathectl_gauge as the sample configuration loads it: its own X of the target size, the
    // thread's period, the signal-lost check.
    const double x_size_m = 0.0125, period_s = 1e-4;
    const auto hal = d_gauging::machine_params(p, g, plan.threshold_V,
                                               {.period_s = period_s,
                                                .target_x_m = x_size_m,
                                                .backstop_tolerance_m = 1e-9,
                                                .signal_lost = 0.05,
                                                .stop_latency_s = 4e-3});
    // What only the host owns, then the rest field by field.
    EXPECT_EQ(rig.period_s, g.step_s());
    EXPECT_EQ(hal.period_s, period_s);
    EXPECT_NEAR(hal.backstop_m - x_size_m, rig.backstop_m - p.target_m, 2e-9);
    EXPECT_EQ(rig.signal_lost_V, 0.0);
    EXPECT_EQ(hal.signal_lost_V, 0.05 * g.free_signal_V());
    // The host's stop latency is taken off the relay's response: the axis stands still t_r after
    // the crossing, as in the rig; a latency longer than t_r cannot be anticipated.
    EXPECT_EQ(rig.relay_response_s, p.relay_response_s);
    EXPECT_EQ(hal.relay_response_s, p.relay_response_s - 4e-3);
    EXPECT_THROW((void)d_gauging::machine_params(
                     p, g, plan.threshold_V, {.stop_latency_s = p.relay_response_s * 1.01}),
                 std::invalid_argument);
    auto same = hal;
    same.relay_response_s = rig.relay_response_s;
    same.period_s = rig.period_s;
    same.backstop_m = rig.backstop_m;
    same.signal_lost_V = rig.signal_lost_V;
    EXPECT_TRUE(same == rig);
    EXPECT_EQ(rig.arm_after_s, 5.0 * d.transducer.filter_time_constant_s);
    EXPECT_EQ(rig.steps.size(), 3u);
    EXPECT_EQ(rig.steps.back().threshold_V, plan.threshold_V);
  }
}

}  // namespace
}  // namespace lathectl::systems
