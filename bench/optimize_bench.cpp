// lathectl optimize's speed: a 10-minute program optimised in under 2 s without
// --verify — LinuxCNC's interpreter twice (read, and the check of the written program), the
// prediction at the servo period twice (programmed and optimised feeds), the feed choice.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "optimize/optimize.hpp"
#include "systems/registry.hpp"

using namespace lathectl;

namespace {

// 34 roughing passes of 0.5 mm at a cautious 0.15 mm/rev over step_allowance.toml's bar (the
// first ones through its collar): 10.1 min predicted at the programmed feeds.
std::string ten_minute_program() {
  std::string p = "G18 G21 G40 G80 G90 G95\nT1 M6\nM3 S1194\nG0 X25 Z5\n";
  char buf[96];
  for (int k = 0; k < 34; ++k) {
    std::snprintf(buf, sizeof buf, "G0 X%.1f Z2\nG1 Z-50 F0.15\nG0 X25\nG0 Z2\n", 19.5 - 0.5 * k);
    p += buf;
  }
  return p + "M5\nM2\n";
}

void BM_Optimize_TenMinuteProgram(benchmark::State& state) {
  if (!std::filesystem::exists("/usr/bin/rs274")) {
    state.SkipWithError("LinuxCNC's rs274 not installed");
    return;
  }
  static const auto lib = io::MaterialLibrary::load_default();
  const auto sc =
      systems::load_scenario(LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance.toml", lib);
  const auto& e = sc.get<systems::e_adaptive::Settings>();
  const auto path = std::filesystem::temp_directory_path() / "lathectl-bench-10min.ngc";
  std::ofstream(path) << ten_minute_program();
  optimize::Options opt;
  opt.ini = LATHECTL_SOURCE_DIR "/hal/config/lathectl-lathe.ini";
  double before = 0.0, after = 0.0;
  for (auto _ : state) {
    const auto p = optimize::read_program(path.string(), opt);
    const auto r = optimize::optimize(p, e, opt);
    before = r.before.cycle_time_s;
    after = r.after.cycle_time_s;
    benchmark::DoNotOptimize(r.ngc.data());
  }
  state.counters["cycle_original_s"] = before;
  state.counters["cycle_optimized_s"] = after;
  std::filesystem::remove(path);
}
BENCHMARK(BM_Optimize_TenMinuteProgram)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

}  // namespace
