// The hand-written loops of hand_loops.hpp beside the rigs' benchmarks (docs/code-layout.md,
// "Speed"): the same simulated time, the same rows recorded (the rig into its sim::Recorder, the
// hand loop into a flat array), configure and warm-up included in both.

#include <benchmark/benchmark.h>

#include "hand_loops.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

using namespace lathectl;

namespace {
io::Scenario load_scenario(const char* name) {
  static const auto lib = io::MaterialLibrary::load_default();
  return systems::load_scenario(std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/") + name,
                                lib);
}

// Beside BM_RigA_60s/<case>: 60 s of simulated machining, rows every record interval.
void BM_HandLoopA(benchmark::State& state, const char* scenario) {
  const auto sc = load_scenario(scenario);
  const auto& cfg = sc.get<systems::a_pulse_feed::Settings>().rig;
  for (auto _ : state) {
    const auto r = bench::hand_loop_a(cfg, sc.run.step_s, sc.run.record_interval_s, 60.0);
    benchmark::DoNotOptimize(r.rows);
  }
}
BENCHMARK_CAPTURE(BM_HandLoopA, finishing_aim, "a_finishing_aim.toml")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HandLoopA, uncontrolled, "a_finishing_none.toml")
    ->Unit(benchmark::kMillisecond);

// Beside BM_RigB_TwinTurret10s: 10 s of feed division's cut (no idle block), the module running.
void BM_HandLoopB_TwinTurret10s(benchmark::State& state) {
  const auto sc = load_scenario("b_twin_feed_division.toml");
  auto b = sc.get<systems::b_chatter::Settings>().rig;
  b.z_end_mm = b.z_start_mm + b.feed_mm_per_rev * b.rpm / 60.0 * 10.0;
  b.idle_block_s = 0.0;
  for (auto _ : state) {
    const auto r = bench::hand_loop_b(b, sc.run.step_s, sc.run.record_interval_s, 12.0);
    benchmark::DoNotOptimize(r.rows);
  }
}
BENCHMARK(BM_HandLoopB_TwinTurret10s)->Unit(benchmark::kMillisecond);

}  // namespace
