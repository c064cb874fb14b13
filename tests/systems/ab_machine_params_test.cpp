// Issue 43, one description per system: for systems A and B, every example scenario's machine
// parameters are the same whichever host builds them — the rig (`lathectl run`) or the LinuxCNC
// component with the module parameters the sample configurations use — on every field the host
// does not own, and the rig really runs what machine_params() gives.
//
//   A (control::SlideMachine): rig A, and lathectl_slide (Host::machine_io). No field is the
//     host's: the whole Params compare equal. The scenarios a machine cannot run (an uncontrolled
//     slide, a throttle) are refused by the machine host, at controller.type.
//   B (control::ModulationMachine): rig B (the feeds to the drives, its periods rounded to its
//     step), lathectl_modfeed output=eoffset (hal/config/lathectl-twin.hal) and the default
//     output=adaptive ceiling=2 (tests/hal/modfeed_test.py). The host's fields: module.period_s,
//     vibration.sample_period_s, output, ceiling, and with the factor output the staircase's
//     ceiling on s_max_fraction (min(scenario's, ceiling)).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/registry.hpp"
#include "systems/a_pulse_feed/machine_params.hpp"
#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/machine_params.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl {
namespace {

namespace fs = std::filesystem;
using test::library;

// Every example of a system: examples/scenarios/<prefix>*.toml and the LinuxCNC examples whose
// `system` is `letter` (examples/linuxcnc/*.toml).
std::vector<std::string> examples(const std::string& prefix, const std::string& letter) {
  std::vector<std::string> out;
  const fs::path root = LATHECTL_SOURCE_DIR "/examples";
  for (const auto& e : fs::directory_iterator(root / "scenarios"))
    if (e.path().extension() == ".toml" && e.path().filename().string().starts_with(prefix))
      out.push_back(e.path().string());
  for (const auto& e : fs::directory_iterator(root / "linuxcnc")) {
    if (e.path().extension() != ".toml") continue;
    const std::string text = io::read_scenario_text(e.path().string());
    if (text.find("system = \"" + letter + "\"") != std::string::npos)
      out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// ---- System A ----

TEST(MachineParamsA, EveryExampleTheSameOnTheRigAndInLathectlSlide) {
  namespace a = systems::a_pulse_feed;
  const auto files = examples("a_", "A");
  ASSERT_GE(files.size(), 13u);
  int machines = 0;
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    // Each host reads the scenario as it does: lathectl run with every system's reader and the
    // cross-checks, the component with A's reader alone.
    const auto sc = systems::load_scenario(f, library());
    const auto hal_sc = io::load_scenario(f, library(), a::kReadSection);
    const auto& cfg = sc.get<a::Settings>().rig;
    const auto rig_params = a::machine_params(cfg, a::Host{});

    a::Rig rig;
    rig.set_streamed(true, false);
    rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s,
                  std::min(sc.run.duration_s, sc.run.step_s * 4));
    EXPECT_TRUE(rig.machine().params() == rig_params) << "the rig runs machine_params()";
    EXPECT_EQ(rig.nominal_force_N(), a::nominal_force_N(cfg));

    const auto& hal_cfg = hal_sc.get<a::Settings>().rig;
    const bool machine = cfg.regulator_kind == a::RegulatorKind::Pulsed &&
                         cfg.controller_kind != a::ControllerKind::None;
    if (!machine) {
      EXPECT_THROW((void)a::machine_params(hal_cfg, a::Host{.machine_io = true}),
                   std::invalid_argument);
      continue;
    }
    ++machines;
    const auto hal_params = a::machine_params(hal_cfg, a::Host{.machine_io = true});
    EXPECT_TRUE(hal_params == rig_params) << "lathectl_slide runs what the rig runs";
    EXPECT_EQ(a::nominal_force_N(hal_cfg), rig.nominal_force_N()) << "and starts where it does";
  }
  EXPECT_GE(machines, 7);  // a_*_aim/fim, a_sensor_dropout and the three LinuxCNC examples
}

// ---- System B ----

using FeedOutput = control::ModulationMachine::FeedOutput;

// The fields no host owns: every one but the periods, the feed out and the ceiling.
control::ModulationMachine::Params scenario_part(control::ModulationMachine::Params p) {
  p.module.period_s = 0.0;
  p.vibration.sample_period_s = 0.0;
  p.output = FeedOutput::Drives;
  p.ceiling = 1.0;
  return p;
}

TEST(MachineParamsB, EveryExampleTheSameOnTheRigAndInLathectlModfeed) {
  namespace b = systems::b_chatter;
  const auto files = examples("b_", "B");
  ASSERT_GE(files.size(), 6u);
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    const auto sc = systems::load_scenario(f, library());
    const auto hal_sc = io::load_scenario(f, library(), b::kReadSection);
    const auto& cfg = sc.get<b::Settings>().rig;
    const double dt = sc.run.step_s;
    // The rig's host: the module and sensor periods as whole numbers of its step.
    const b::Host rig_host{
        .module_period_s = dt * static_cast<double>(std::max(1L, std::lround(1e-3 / dt))),
        .sample_period_s = dt * static_cast<double>(std::max(1L, std::lround(1e-4 / dt)))};
    const auto rig_params = b::machine_params(cfg, rig_host);

    b::Rig rig;
    rig.set_streamed(true, false);
    rig.configure(cfg, dt, sc.run.record_interval_s, sc.run.duration_s);
    EXPECT_TRUE(rig.machine().params() == rig_params) << "the rig runs machine_params()";
    EXPECT_EQ(rig_params.output, FeedOutput::Drives);
    EXPECT_NEAR(rig_params.module.period_s, b::kModulePeriod_s, 0.5 * dt);

    const auto& hal_cfg = hal_sc.get<b::Settings>().rig;
    // hal/config/lathectl-twin.hal: output=eoffset, the thread the servo thread (1 ms).
    const auto twin = b::machine_params(hal_cfg, b::Host{.output = FeedOutput::Offset});
    EXPECT_TRUE(scenario_part(twin) == scenario_part(rig_params))
        << "output=eoffset runs the rig's machine";
    EXPECT_EQ(twin.module.period_s, b::kModulePeriod_s);
    EXPECT_EQ(twin.ceiling, 1.0);
    // The default output=adaptive, ceiling=2: the staircase under the program's F.
    const auto factor =
        b::machine_params(hal_cfg, b::Host{.output = FeedOutput::Factor, .ceiling = 2.0});
    auto capped = scenario_part(rig_params);
    capped.module.s_max_fraction = std::min(capped.module.s_max_fraction, 2.0);
    EXPECT_TRUE(scenario_part(factor) == capped) << "output=adaptive: the rig's, S_max ≤ 2·S_p";
    EXPECT_EQ(factor.ceiling, 2.0);
  }
}

TEST(MachineParamsB, AHostsCeilingIsChecked) {
  namespace b = systems::b_chatter;
  const auto sc = io::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/b_chatter_single.toml",
                                    library(), b::kReadSection);
  const auto& cfg = sc.get<b::Settings>().rig;
  for (double c : {0.5, 1.0, 101.0})
    EXPECT_THROW((void)b::machine_params(cfg, b::Host{.output = FeedOutput::Factor, .ceiling = c}),
                 std::invalid_argument)
        << c;
}

}  // namespace
}  // namespace lathectl
