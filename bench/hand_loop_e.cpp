// BM_HandLoopE: rig E's cutting process written out by hand (hand_loop_e.hpp) on the tool path
// the rig runs for a whole part (its plant's inputs, step by step, recorded before the timing),
// against BM_RigE_Part (the rig: cutting process, machine side, drives, recording) and
// BM_RigE_Cut (the library's plant alone on the same path). Issue 45 item 6: the rig's cut
// against a loop of the same equations.

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "hand_loop_e.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

using namespace lathectl;

namespace {

struct Path {
  cutting::CuttingProcess process;
  double dt = 0.0;
  std::vector<cutting::LathePlant::Input> steps;
};

// The plant's inputs of every step of the rig's part.
const Path& path(const char* scenario) {
  static std::string name;
  static Path p;
  if (name == scenario) return p;
  static const auto lib = io::MaterialLibrary::load_default();
  const auto sc = systems::load_scenario(
      std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/") + scenario, lib);
  const auto& cfg = sc.get<systems::e_adaptive::Settings>().rig;
  systems::e_adaptive::Rig rig;
  rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
  p = {systems::e_adaptive::lathe_process(cfg), sc.run.step_s, {}};
  p.process.faults.clear();
  while (rig.step()) p.steps.push_back(rig.cut_input());
  name = scenario;
  return p;
}

void BM_HandLoopE(benchmark::State& state, const char* scenario) {
  const Path& p = path(scenario);
  double sum = 0.0;
  for (auto _ : state) {
    bench::HandCutE cut;
    cut.configure(p.process);
    bench::HandCutE::Out out;
    for (const auto& in : p.steps) {
      cut.step(in.x_mm, in.z_mm, in.rpm, p.dt, out);
      sum += out.force_measured;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.counters["steps"] = static_cast<double>(p.steps.size());
}
BENCHMARK_CAPTURE(BM_HandLoopE, seed004, "e_stepped_seed004.toml")->Unit(benchmark::kMillisecond);

void BM_RigE_Cut(benchmark::State& state, const char* scenario) {
  const Path& p = path(scenario);
  double sum = 0.0;
  for (auto _ : state) {
    cutting::LathePlant plant;
    plant.configure(p.process, {});
    cutting::LathePlant::Output out;
    for (const auto& in : p.steps) {
      plant.step(in, p.dt, out);
      sum += out.force_measured;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.counters["steps"] = static_cast<double>(p.steps.size());
}
BENCHMARK_CAPTURE(BM_RigE_Cut, seed004, "e_stepped_seed004.toml")->Unit(benchmark::kMillisecond);

}  // namespace
