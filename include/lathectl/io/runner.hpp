#pragma once
// Scenario → rig → runner → recorder → report: what a run's output is, how a study runs its rigs,
// and how the output is written (summary.json, channels.csv and channels_compare.csv,
// report.html) into an output directory. Running a scenario of any system is the systems
// layer's (systems::run_scenario in src/systems/registry.hpp, which knows them all); this layer
// (lathectl_io, src/io/runner.cpp) knows none.

#include <concepts>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/verdict.hpp"

namespace lathectl::io {

struct RunOutput {
  nlohmann::json summary;  // {"system", "scenario", "metrics", ...}
  // channels.csv and channels_compare.csv (empty when no comparison) — or empty when the run
  // streamed them into the StreamScope's stage (open_channel_stream).
  std::string channels_csv;
  std::string compare_csv;
  // channels.csv's columns at full precision, kept only while a ChannelStream::KeepValues lives.
  ChannelValues channels_values;
  Report report;
  std::string headline;  // one line for the demo index
  Verdict verdict;       // unmet claims, alarms, unfinished parts (also summary["verdict"])
};

// What every run's output gets after its system's study ran (systems::run_scenario, which runs
// the scenario's system, calls it): the settings, the warnings, and the verdict, filled in, added
// to the summary and shown at the top of the report.
void finish_run(const Scenario& sc, RunOutput& out);
// The report's settings table: every key the scenario's reader read, in the file's units, with
// the unit and default its description gives (finish_run adds it; tests compare it).
Table settings_table(const Scenario& sc);
// index_href: the demo's index.html relative to dir ("../index.html"), linked from the report;
// empty for a single run.
void write_outputs(const RunOutput& out, const std::filesystem::path& dir,
                   const std::string& index_href = {});
// Into a stage made before the run (the runs may have streamed channels.csv into it).
void write_outputs(const RunOutput& out, OutputStage& stage, const std::string& index_href = {});

// Configures a rig with the scenario's run settings and runs it to the end. A configuration the
// rig rejects is the scenario's fault (InputError); a divergence is a numerical failure
// (std::runtime_error). Every system's study runs its rigs through this.
template <class Rig, class Config>
void configure_rig(const Scenario& sc, Rig& rig, const Config& cfg) {
  try {
    if constexpr (requires { rig.configure(cfg, 0.0, 0.0, 0.0); })
      rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
    else
      rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s);
  } catch (const std::invalid_argument& e) {
    throw_at_key(sc, e);
  }
}

// Runs a configured rig to the end (configure_rig first; between the two a study may attach
// sinks to the rig's recorder).
template <class Rig>
void run_rig(const Scenario& sc, Rig& rig, const std::string& divergence = "NaN or infinite state") {
  Progress* progress = ProgressScope::current();
  if constexpr (requires { { rig.step() } -> std::same_as<bool>; }) {
    if (progress && progress->enabled()) {  // the same steps as rig.run(), reported as they go
      const std::string what = "simulation " + std::to_string(ProgressScope::next_simulation());
      std::size_t n = 0;
      while (rig.step())
        if (++n % 16384 == 0) {
          double t = 0.0;
          if constexpr (requires { rig.time_s(); }) t = rig.time_s();
          if constexpr (requires { rig.cycle_time_s(); }) t = rig.cycle_time_s();
          progress->update(t / sc.run.duration_s, what);
        }
    } else {
      rig.run();
    }
  } else {
    if (progress) progress->update(0.0, "simulation " +
                                            std::to_string(ProgressScope::next_simulation()));
    rig.run();
  }
  if (!rig.numerically_sound())
    throw std::runtime_error(sc.file + ": the simulation diverged (" + divergence +
                             "); reduce run.step_s");
}

template <class Rig, class Config>
void configure_and_run(const Scenario& sc, Rig& rig, const Config& cfg,
                       const std::string& divergence = "NaN or infinite state") {
  configure_rig(sc, rig, cfg);
  run_rig(sc, rig, divergence);
}

}  // namespace lathectl::io
