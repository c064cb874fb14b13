// Benchmarks: simulation step rate of each rig, controller update() time, and the hot models.
// Run with `make bench`. The targets: 60 s of simulated machining in < 0.1 s of wall
// time on one core (BM_RigA_60s), controller update() well under a microsecond.

#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/control/modulated_feed.hpp"
#include "lathectl/control/pulse_feed_controller.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sim/recorder.hpp"
#include "support/sample_controller.hpp"
#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/d_gauging/rig.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

using namespace lathectl;

namespace {
io::Scenario load(const char* name) {
  static const auto lib = io::MaterialLibrary::load_default();
  return systems::load_scenario(std::string(LATHECTL_SOURCE_DIR "/examples/scenarios/") + name,
                                lib);
}

void BM_RigA_60s(benchmark::State& state, const char* scenario) {
  const auto sc = load(scenario);
  const double duration = 60.0;
  for (auto _ : state) {
    systems::a_pulse_feed::Rig rig;
    rig.configure(sc.get<systems::a_pulse_feed::Settings>().rig, sc.run.step_s,
                  sc.run.record_interval_s, duration);
    rig.run();
    benchmark::DoNotOptimize(rig.recorder().rows());
  }
  const double steps = duration / sc.run.step_s;
  state.counters["sim_s_per_wall_s"] = benchmark::Counter(
      duration * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["steps_per_s"] = benchmark::Counter(
      steps * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_RigA_60s, finishing_aim, "a_finishing_aim.toml")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RigA_60s, finishing_fim, "a_finishing_fim.toml")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RigA_60s, roughing_fim_all_disturbances, "a_roughing_fim.toml")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RigA_60s, uncontrolled, "a_finishing_none.toml")
    ->Unit(benchmark::kMillisecond);

// System E: one whole part (the target: a 5-minute part in < 0.5 s of wall time).
void BM_RigE_Part(benchmark::State& state, const char* scenario) {
  const auto sc = load(scenario);
  double cycle = 0.0;
  for (auto _ : state) {
    systems::e_adaptive::Rig rig;
    rig.configure(sc.get<systems::e_adaptive::Settings>().rig, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
    rig.run();
    cycle = rig.cycle_time_s();
    benchmark::DoNotOptimize(rig.recorder().rows());
  }
  state.counters["part_cycle_s"] = cycle;
  state.counters["sim_s_per_wall_s"] = benchmark::Counter(
      cycle * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_RigE_Part, seed004, "e_stepped_seed004.toml")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RigE_Part, fixed_worst_case, "e_stepped_fixed.toml")
    ->Unit(benchmark::kMillisecond);

// The seed's linearisation (A0, K) of a gauging scenario's transducer and its threshold (23).
std::pair<systems::d_gauging::LinearGauge, double> seed_line(const io::Scenario& sc) {
  const auto& d = sc.get<systems::d_gauging::Settings>();
  const auto st = sensors::VibroContactGauge::steady(d.transducer);
  // With the scenario's filter (d_gauging: synchronous, simulated by steps).
  const systems::d_gauging::LinearGauge lg =
      systems::d_gauging::linear_gauge({st.signal_gain_V_per_m, st.free_amplitude_m}, d.transducer);
  return {lg, systems::d_gauging::threshold_23(lg, d.process)};
}

// System D: 10^5 parts by the linearised model (target < 2 s), one part by the full
// electromechanical model (target < 50 ms).
void BM_Gauging_LinearMonteCarlo(benchmark::State& state) {
  const auto sc = load("d_gauging.toml");
  const auto [lg, th] = seed_line(sc);
  for (auto _ : state) {
    auto r = systems::d_gauging::monte_carlo_linear(
        sc.get<systems::d_gauging::Settings>().process, lg, th,
        static_cast<std::size_t>(state.range(0)), 7, static_cast<unsigned>(state.range(1)));
    benchmark::DoNotOptimize(r.data());
  }
}
BENCHMARK(BM_Gauging_LinearMonteCarlo)
    ->Args({100000, 0})
    ->Args({100000, 1})
    ->ArgNames({"parts", "threads"})
    ->Unit(benchmark::kMillisecond);

void BM_Gauging_FullModelPart(benchmark::State& state) {
  const auto sc = load("d_gauging.toml");
  const auto [lg, th] = seed_line(sc);
  const auto& d = sc.get<systems::d_gauging::Settings>();
  std::uint64_t seed = 1;
  for (auto _ : state) {
    auto r =
        systems::d_gauging::machine_part_full(d.process, d.transducer, sc.run.step_s, th, seed++);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_Gauging_FullModelPart)->Unit(benchmark::kMillisecond);

// System B, layer 1: lobes over 1000 speeds by the frequency domain (target < 50 ms), the
// semi-discretization limit at one speed by bisection, the SD chart (below), 10 s of
// time-domain chatter at 50 steps per vibration period (target < 0.5 s).
dynamics::ChatterSystem bench_sdof() {
  dynamics::ChatterSystem s;
  s.kf_N_per_m2 = 1e9;
  s.modes = {{2.26e8, 0.012, 250.0, 30.0 * std::numbers::pi / 180.0}};
  return s;
}
void BM_Lobes_FrequencyDomain(benchmark::State& state) {
  const auto s = bench_sdof();
  for (auto _ : state)
    benchmark::DoNotOptimize(dynamics::frequency_domain_lobes(s, 2000, 14000, 40, 1000));
}
BENCHMARK(BM_Lobes_FrequencyDomain)->Unit(benchmark::kMillisecond);
void BM_Lobes_SemiDiscretizationOneSpeed(benchmark::State& state) {
  const auto s = bench_sdof();
  for (auto _ : state)
    benchmark::DoNotOptimize(dynamics::sd_limit_depth(s, 9500.0, 0.03, 20, 1e-2));
}
BENCHMARK(BM_Lobes_SemiDiscretizationOneSpeed)->Unit(benchmark::kMillisecond);
// The SD stability chart, 200 speeds × 100 depths (0..30 mm) over 2000–14000 rpm, SD with
// quintic interpolation at 7 steps per vibration period (m = 20..53), on every hardware thread
// (target < 5 s).
void BM_Lobes_SdChart200x100(benchmark::State& state) {
  const auto s = bench_sdof();
  for (auto _ : state)
    benchmark::DoNotOptimize(dynamics::sd_stability_chart(s, 2000, 14000, 200, 0.03, 100));
}
BENCHMARK(BM_Lobes_SdChart200x100)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// The cost of one SD chart cell against the steps per delay m (the eigenvalue solve of
// the (2 + m + 2)-dimensional map; the example mode at 6500 rpm and 5 mm).
void BM_Lobes_SdCellEigen(benchmark::State& state) {
  const auto s = bench_sdof();
  const int m = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(dynamics::spectral_radius_sd(s, 6500.0, 5e-3, m, 5));
}
BENCHMARK(BM_Lobes_SdCellEigen)->Arg(54)->Arg(101)->Arg(201)->Arg(400)->ArgName("m")
    ->Unit(benchmark::kMillisecond);
// The same cell as the chart now evaluates it: the number of the SD map's roots outside the unit
// circle by the argument principle, cost ∝ m.
void BM_Lobes_SdCellCount(benchmark::State& state) {
  const auto s = bench_sdof();
  const int m = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(dynamics::sd_unstable_roots(s, 6500.0, 5e-3, m, 5));
}
BENCHMARK(BM_Lobes_SdCellCount)->Arg(54)->Arg(101)->Arg(201)->Arg(400)->ArgName("m")
    ->Unit(benchmark::kMillisecond);

// The default SD chart of each machine file (as `lathectl lobes` draws it: its own
// speeds × depths, top 4 × the absolute limit unless the file sets it) on 2 threads (target:
// under 5 s for any machine file). b_slow_high_freq: one 650 Hz mode at 500–4000 rpm.
void BM_Lobes_SdChartMachine(benchmark::State& state, const char* machine) {
  const auto in = systems::b_chatter::load_lobes_input(
      std::string(LATHECTL_SOURCE_DIR "/examples/machines/") + machine);
  const auto fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes,
                                                   40000);
  const double top = in.chart_max_depth_m > 0.0 ? in.chart_max_depth_m : 4.0 * fd.critical_depth_m;
  dynamics::SdChartOptions o;
  o.steps_per_period = in.chart_steps_per_period;
  o.threads = 2;
  int m_max = 0;
  for (auto _ : state) {
    const auto c = dynamics::sd_stability_chart(in.system, in.min_rpm, in.max_rpm, in.chart_speeds,
                                                top, in.chart_depths, o);
    m_max = *std::max_element(c.steps.begin(), c.steps.end());
    benchmark::DoNotOptimize(c.boundary_depth_m.data());
  }
  state.counters["cells"] = in.chart_speeds * in.chart_depths;
  state.counters["m_max"] = m_max;
}
BENCHMARK_CAPTURE(BM_Lobes_SdChartMachine, b_sdof, "b_sdof.toml")
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_Lobes_SdChartMachine, b_two_mode, "b_two_mode.toml")
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_Lobes_SdChartMachine, b_part, "b_part.toml")
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_Lobes_SdChartMachine, b_slow_high_freq, "b_slow_high_freq.toml")
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The limit depth at one speed read off the frequency-domain lobes (`lobes` asks it
// 1001 times for lobes.csv, and once per SD speed); b_part's lobes (60 lobes, 40000 points).
void BM_Lobes_EnvelopeDepth(benchmark::State& state) {
  const auto in = systems::b_chatter::load_lobes_input(
      std::string(LATHECTL_SOURCE_DIR "/examples/machines/b_part.toml"));
  const auto fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes,
                                                   40000);
  std::size_t points = 0;
  for (const auto& l : fd.lobes) points += l.points.size();
  double n = in.min_rpm;
  for (auto _ : state) {
    n = n >= in.max_rpm ? in.min_rpm : n + 1.7;
    benchmark::DoNotOptimize(dynamics::envelope_depth(fd, n));
  }
  state.counters["lobe_points"] = static_cast<double>(points);
}
BENCHMARK(BM_Lobes_EnvelopeDepth)->Unit(benchmark::kMicrosecond);

// Writing channels.csv: 100 000 rows of 12 channels (typical magnitudes).
void BM_Output_ChannelsCsv(benchmark::State& state) {
  std::vector<sim::Channel> ch;
  for (int i = 0; i < 12; ++i) ch.push_back({"channel_" + std::to_string(i), ""});
  const std::size_t rows = 100000;
  sim::Recorder rec(ch, rows);
  std::vector<double> row(12);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < 12; ++i)
      row[i] = std::sin(0.001 * static_cast<double>(r) * static_cast<double>(i + 1)) *
               std::pow(10.0, static_cast<double>(i) - 4.0);
    rec.push_row(row);
  }
  std::size_t bytes = 0;
  for (auto _ : state) {
    const auto s = io::channels_csv(rec);
    bytes = s.size();
    benchmark::DoNotOptimize(s.data());
  }
  state.counters["bytes_per_s"] = benchmark::Counter(
      static_cast<double>(bytes) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
  state.counters["rows_per_s"] = benchmark::Counter(
      static_cast<double>(rows) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Output_ChannelsCsv)->Unit(benchmark::kMillisecond);

// A run's memory does not grow with its duration. Rows of system E's 22 channels pushed
// into a streamed recorder (channels.csv written to a temporary file as they come, a bounded
// min/max plot per channel): peak_rss_MB (the process's peak resident set so far) stays the same
// from 1e6 to 4e6 rows (the recorder with columns held 8 B per value, channels.csv and the plot
// copies about 500 B per row more).
void BM_Output_StreamedRecorder(benchmark::State& state) {
  std::vector<sim::Channel> ch;
  for (int i = 0; i < 22; ++i) ch.push_back({"channel_" + std::to_string(i), ""});
  const auto rows = static_cast<std::size_t>(state.range(0));
  const auto file = std::filesystem::temp_directory_path() /
                    ("lathectl_bench_stream_" + std::to_string(::getpid()) + ".csv");
  std::vector<double> row(ch.size());
  for (auto _ : state) {
    io::ChannelStream csv(ch, file);
    auto rec = sim::Recorder::streamed(ch, {&csv});
    for (std::size_t r = 0; r < rows; ++r) {
      row[0] = 0.01 * static_cast<double>(r);
      for (std::size_t i = 1; i < ch.size(); ++i)
        row[i] = std::sin(0.001 * static_cast<double>(r) * static_cast<double>(i)) *
                 std::pow(10.0, static_cast<double>(i % 8) - 4.0);
      rec.push_row(row);
    }
    csv.finish();
    benchmark::DoNotOptimize(rec.rows());
  }
  std::filesystem::remove(file);
  rusage ru{};
  ::getrusage(RUSAGE_SELF, &ru);
  state.counters["peak_rss_MB"] = static_cast<double>(ru.ru_maxrss) / 1024.0;
  state.counters["rows_per_s"] = benchmark::Counter(
      static_cast<double>(rows) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Output_StreamedRecorder)->Arg(1000000)->Arg(4000000)->Iterations(1)->Unit(benchmark::kSecond);
// The cost of one recorded row of rig A (17 channels, a row every 2 ms of a run): 30 000 rows
// (a minute) pushed into 0 the columns (Recorder with a capacity: BM_RigA_60s), 1 a streamed
// recorder's plots (the bounded pyramids), 2 the plots and channels.csv's text (a ChannelStream
// in memory: what `lathectl run` formats, less the disk). s_per_row: the time per row.
void BM_Output_RecordRowA(benchmark::State& state) {
  std::vector<sim::Channel> ch;
  for (int i = 0; i < 17; ++i) ch.push_back({"channel_" + std::to_string(i), ""});
  constexpr std::size_t kRows = 30000;
  std::vector<double> rows(kRows * ch.size());
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t i = 0; i < ch.size(); ++i)
      rows[r * ch.size() + i] = i == 0 ? 0.002 * static_cast<double>(r + 1)
                                       : std::sin(0.001 * static_cast<double>(r) * static_cast<double>(i)) *
                                             std::pow(10.0, static_cast<double>(i % 8) - 4.0);
  for (auto _ : state) {
    io::ChannelStream csv(ch);
    auto rec = state.range(0) == 0 ? sim::Recorder(ch, kRows)
               : state.range(0) == 1 ? sim::Recorder::streamed(ch)
                                     : sim::Recorder::streamed(ch, {&csv});
    for (std::size_t r = 0; r < kRows; ++r)
      rec.push_row(std::span<const double>(rows.data() + r * ch.size(), ch.size()));
    benchmark::DoNotOptimize(rec.rows());
    benchmark::DoNotOptimize(csv.text().size());
  }
  state.counters["s_per_row"] = benchmark::Counter(
      static_cast<double>(kRows) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Output_RecordRowA)->Arg(0)->Arg(1)->Arg(2)->ArgName("store")->Unit(benchmark::kMillisecond);
void BM_Chatter_TimeDomain10s(benchmark::State& state) {
  const auto s = bench_sdof();
  for (auto _ : state)
    benchmark::DoNotOptimize(dynamics::time_domain(s, 5500.0, 7e-3, 1e-4, 10.0, 50));
}
BENCHMARK(BM_Chatter_TimeDomain10s)->Unit(benchmark::kMillisecond);

void BM_AdaptiveFeedController_Update(benchmark::State& state) {
  control::AdaptiveFeedController::Params p;
  p.mode = static_cast<control::AdaptiveFeedController::Mode>(state.range(0));
  p.load_limit = 2500.0;
  p.feed_programmed_mm_per_rev = 0.5;
  p.sensor_monitor = {-500.0, 20000.0, 0.1, 0.0};
  control::AdaptiveFeedController c;
  c.configure(p);
  control::AdaptiveFeedController::Output out;
  double k = 0.0;
  for (auto _ : state) {
    control::AdaptiveFeedController::Input in;
    in.force = 2400.0 + 200.0 * std::sin(k);
    in.feed_rate_mm_per_min = 150.0;
    in.rpm = 600.0;
    in.speed_m_per_min = 160.0;
    in.cut_power_W = 6000.0;
    k += 0.01;
    c.update(in, out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_AdaptiveFeedController_Update)->Arg(0)->Arg(1)->Arg(2)->ArgName("mode");

void BM_PulseFeedController_Update(benchmark::State& state) {
  const auto p = testing::sample_pulse_feed_params(
      state.range(0) ? control::PulseFeedController::Modulation::Frequency
                     : control::PulseFeedController::Modulation::Amplitude,
      state.range(1) ? control::PulseFeedController::Mode::Roughing
                     : control::PulseFeedController::Mode::Finishing);
  control::PulseFeedController c;
  c.configure(p);
  control::PulseFeedController::Output out;
  double k = 0.0;
  for (auto _ : state) {
    control::PulseFeedController::Input in{1.0 + 0.2 * std::sin(k)};
    k += 0.001;
    c.update(in, out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_PulseFeedController_Update)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"fim", "roughing"});

void BM_PulseRegulator_Step(benchmark::State& state) {
  hydraulics::PulseRegulator::Params p;
  p.orifice = {0.005, 0.65, 0.2e6, 870.0};
  p.max_slot_m = 1e-4;
  p.opening_time_s = 5e-4;
  p.closing_time_s = 5e-4;
  hydraulics::PulseRegulator reg;
  reg.configure(p);
  for (auto _ : state) benchmark::DoNotOptimize(reg.step(1e-4, 40e-6, 20.0, 0.005));
}
BENCHMARK(BM_PulseRegulator_Step);

void BM_CuttingModel_RadialForce(benchmark::State& state) {
  const auto lib = io::MaterialLibrary::load_default();
  cutting::CuttingModel m;
  m.configure({*lib.find("steel_45"), cutting::ForceForm::Handbook, 90.0, 0.8});
  double s = 0.1;
  for (auto _ : state) {
    s = s > 0.5 ? 0.1 : s + 1e-6;
    benchmark::DoNotOptimize(m.radial_force({1.0, s, 100.0, 1.1, 1.05}));
  }
}
BENCHMARK(BM_CuttingModel_RadialForce);

// System B rig: 10 s of twin-turret chatter (feed division, two modes following the tool, the
// measurement chain and the module running) at 2e-5 s = 220 steps per 227 Hz vibration period
// (target: 10 s at ≥ 50 steps per period in < 0.5 s).
void BM_RigB_TwinTurret10s(benchmark::State& state) {
  const auto sc = load("b_twin_feed_division.toml");
  auto b = sc.get<systems::b_chatter::Settings>().rig;
  b.z_end_mm = b.z_start_mm + b.feed_mm_per_rev * b.rpm / 60.0 * 10.0;
  b.idle_block_s = 0.0;
  for (auto _ : state) {
    systems::b_chatter::Rig rig;
    rig.configure(b, sc.run.step_s, sc.run.record_interval_s, 12.0);
    rig.run();
    benchmark::DoNotOptimize(rig.recorder().rows());
  }
  state.counters["steps_per_period"] = 1.0 / (227.0 * sc.run.step_s);
}
BENCHMARK(BM_RigB_TwinTurret10s)->Unit(benchmark::kMillisecond);

// A cutting block vibrating at 227 Hz with amplitude a0 [m].
control::ModulatedFeedController::Input modfeed_input(double a0) {
  control::ModulatedFeedController::Input in;
  in.a0_m = a0;
  in.omega_d_rad_per_s = 2.0 * std::numbers::pi * 227.0;
  in.cut_power_W = 500.0;
  in.speed_m_per_min = 100.0;
  in.rpm = 800.0;
  in.feed_programmed_mm_per_min[0] = in.feed_programmed_mm_per_min[1] = 100.0;
  in.feed_block = true;
  return in;
}

void BM_ModulatedFeedController_Update(benchmark::State& state) {
  control::ModulatedFeedController m;
  m.configure({});
  auto in = modfeed_input(10e-6);
  control::ModulatedFeedController::Output out;
  for (auto _ : state) {
    in.path_mm[0] += 1.6e-3;
    m.update(in, out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_ModulatedFeedController_Update);
// The module's re-plan (quenching condition, mean-keeping S_min, quanta) runs inside update()
// when a0 grows: its cost bounds the real-time worst case.
// Arg: n_s (the scenario accepts 1..1000).
void BM_ModulatedFeedController_Plan(benchmark::State& state) {
  control::ModulatedFeedController m;
  control::ModulatedFeedController::Params mp;
  mp.n_s = static_cast<int>(state.range(0));
  m.configure(mp);
  double wm = 0, req = 0, got = 0, a0 = 1e-5;
  bool lim = false;
  for (auto _ : state) {
    a0 = a0 > 1e-4 ? 1e-5 : a0 * 1.01;
    benchmark::DoNotOptimize(m.plan_for(a0, 2.0 * std::numbers::pi * 230.0, 1000.0, 100.0, 246.0,
                                        820.0, wm, req, got, lim));
  }
}
BENCHMARK(BM_ModulatedFeedController_Plan)->Arg(5)->Arg(32)->Arg(33)->Arg(50)->Arg(1000)->Unit(benchmark::kMicrosecond);

// update()'s worst case when the re-plan runs in the planner's thread
// (ModulationPlanner, lathectl-modfeed.plan): a0 grows every call and the re-plan period is one
// call, so the calls alternate between posting a request and taking the finished plan (the two
// re-plan paths); the planning in between is not timed. Manual time: the update() calls alone
// (steady clock around each); p50_ns, p99_ns, p999_ns and max_ns of the calls (on a loaded
// machine the largest are preemptions, not the code: its path has no loop but the staircase's).
// Arg: n_s.
void BM_ModulatedFeedController_UpdateDeferred(benchmark::State& state) {
  control::ModulatedFeedController m;
  control::ModulatedFeedController::Params mp;
  mp.n_s = static_cast<int>(state.range(0));
  mp.engage_time_s = 0.0;
  mp.replan_period_s = mp.period_s;
  m.configure(mp);
  control::ModulationPlanner planner;
  m.use_planner(&planner);
  (void)planner.run(m);  // the planner thread is alive
  auto in = modfeed_input(1e-6);
  control::ModulatedFeedController::Output out;
  std::vector<double> ns;
  ns.reserve(1u << 22);
  std::size_t plans = 0;
  for (auto _ : state) {
    in.path_mm[0] += 1.6e-3;
    in.a0_m += 1e-12;
    const auto t0 = std::chrono::steady_clock::now();
    m.update(in, out);
    benchmark::DoNotOptimize(out);
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.SetIterationTime(dt);
    if (ns.size() < ns.capacity()) ns.push_back(dt * 1e9);
    plans += planner.run(m) ? 1 : 0;  // the slower thread's turn
  }
  std::sort(ns.begin(), ns.end());
  const auto at = [&](double q) {
    return ns.empty() ? 0.0 : ns[static_cast<std::size_t>(q * static_cast<double>(ns.size() - 1))];
  };
  state.counters["p50_ns"] = at(0.5);
  state.counters["p99_ns"] = at(0.99);
  state.counters["p999_ns"] = at(0.999);
  state.counters["max_ns"] = at(1.0);
  state.counters["replans_per_call"] =
      static_cast<double>(plans) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ModulatedFeedController_UpdateDeferred)->Arg(5)->Arg(1000)->UseManualTime()->Unit(benchmark::kNanosecond);
}  // namespace
