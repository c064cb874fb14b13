// The machine objects' update() per call in C++, configured from an example as the rig configures
// them (each system's machine_params), with the inputs python/tests/test_machines.py's timing
// and docs/python.md's table use: what the Python objects' update() (lathectl.SlideMachine, ...)
// adds to it is the binding's cost.
#include <benchmark/benchmark.h>

#include <string>

#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/a_pulse_feed/machine_params.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/machine_params.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/d_gauging/machine_params.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

using namespace lathectl;

namespace {

io::Scenario example(const char* name) {
  static const auto lib = io::MaterialLibrary::load_default();
  return systems::load_scenario(std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/") + name,
                                lib);
}

void BM_MachineUpdate_SlideA(benchmark::State& state) {
  namespace a = systems::a_pulse_feed;
  const auto sc = example("a_roughing_aim.toml");
  const auto& cfg = sc.get<a::Settings>().rig;
  control::SlideMachine m;
  m.configure(a::machine_params(cfg, a::Host{}));
  m.start(a::nominal_force_N(cfg));
  control::SlideMachine::Input in;
  in.mode = m.params().controller.mode;
  in.sensor_V = 2.0;
  for (auto _ : state) {
    m.update(in);
    benchmark::DoNotOptimize(m.output().slot_m);
  }
}
BENCHMARK(BM_MachineUpdate_SlideA);

void BM_MachineUpdate_GaugeD(benchmark::State& state) {
  namespace dg = systems::d_gauging;
  const auto sc = example("d_gauging.toml");
  const auto& d = sc.get<dg::Settings>();
  sensors::VibroContactGauge gauge;
  dg::configure_transducer(sc, gauge);
  const auto plan = dg::plan_threshold(d, sc.run.step_s);
  auto pr = d.process;
  pr.cycle = dg::cycle_for(d.transducer, d.sequence, plan.line, pr, plan.threshold_V);
  control::GaugeMachine m;
  m.configure(dg::machine_params(pr, gauge, plan.threshold_V));
  control::GaugeMachine::Input in;
  in.generator_V = 0.5;
  for (auto _ : state) {
    m.update(in);
    benchmark::DoNotOptimize(m.output().signal_V);
  }
}
BENCHMARK(BM_MachineUpdate_GaugeD);

void BM_MachineUpdate_AdaptiveE(benchmark::State& state) {
  namespace e = systems::e_adaptive;
  const auto sc = example("e_stepped_seed004.toml");
  control::AdaptiveMachine m;
  m.configure(e::machine_params(sc.get<e::Settings>().rig, e::MachineHost{}));
  control::AdaptiveMachine::Input in;
  control::AdaptiveMachine::Output out;
  in.nominal_period_s = sc.run.step_s;
  in.force = 1000.0;
  in.rpm = 500.0;
  in.x_mm = 20.0;
  in.z_mm = -5.0;
  for (auto _ : state) {
    m.update(in, out);
    benchmark::DoNotOptimize(out.feed_factor);
  }
}
BENCHMARK(BM_MachineUpdate_AdaptiveE);

void BM_MachineUpdate_ModulationB(benchmark::State& state) {
  namespace b = systems::b_chatter;
  const auto sc = example("b_twin_feed_division.toml");
  const auto& cfg = sc.get<b::Settings>().rig;
  control::ModulationMachine m;
  m.configure(b::machine_params(cfg, b::Host{}));
  control::ModulationMachine::Input in;
  in.source = cfg.source;
  in.turret = cfg.turret;
  in.motor_power_W = 1000.0;
  for (auto _ : state) {
    m.sense(1e-6);
    m.update(in);
    benchmark::DoNotOptimize(m.output().factor);
  }
}
BENCHMARK(BM_MachineUpdate_ModulationB);

}  // namespace
