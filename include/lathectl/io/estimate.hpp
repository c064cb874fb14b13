#pragma once
// What a scenario will cost before it runs (`lathectl check`): the simulated steps and parts its
// study runs, the CPU time that takes, and the size of the output set. Each system's registry
// entry (src/systems/registry.cpp) points at its own model of its study's loops (which runs,
// sweeps and Monte Carlo parts it makes: src/systems/<folder>/estimate.cpp), a cost per step or
// per part measured on the examples (docs/scenario-reference.md, "What a run costs") times the
// steps; what they share is here. The time is an estimate within a factor of about two, the
// steps and rows are counted exactly where the scenario fixes them and as upper bounds where the
// part decides (E ends when the last pass does, C when the template is traced).

#include <string>

#include "lathectl/io/scenario.hpp"

namespace lathectl::io {

struct RunEstimate {
  double simulated_steps = 0.0;  // rig steps over every run of the study
  double parts = 0.0;            // Monte Carlo parts (system D), linearised and full model
  double cpu_s = 0.0;            // CPU time on one core of the reference machine
  double wall_s = 0.0;           // on this machine's cores, as the study spreads its runs
  double output_bytes = 0.0;     // the output set: channels CSVs and the report
  std::string breakdown;         // "3 runs × 1.2e+06 steps" …
  bool upper_bound = false;      // E: every run may end sooner (with the part)
};

// CPU seconds per simulated step and bytes per recorded row of one run's channels CSV: fitted to
// the examples' `lathectl run` (user time on the 2-core CI machine, Debian 12, x86-64, -O2,
// 2026-11-26; docs/scenario-reference.md, "What a run costs").
struct StepCosts {
  double step_s;
  double row_bytes;
};
constexpr double kReportBytes = 1.0e6;  // report.html and summary.json, about

// An estimate's start: the report and summary, nothing run yet.
RunEstimate report_only();
// Adds `runs` rig runs of the scenario's run.duration_s / run.step_s steps each, `parallel` of
// them at a time at most, `recorded_runs` of them writing their channels.
void add_rig_runs(RunEstimate& e, const Scenario& sc, double runs, double parallel, StepCosts c,
                  double recorded_runs);
// The cores a study spreads its runs over (≥ 1).
double estimate_cores();
// A count in a breakdown: "120000", "1.2e+06".
std::string count_text(double v);

// "about 3 min", "about 2.1 h" ("at most …" with upper_bound); "about 1.5 GB".
std::string duration_text(double seconds, bool upper_bound = false);
std::string size_text(double bytes, bool upper_bound = false);
// One line: "2 runs × 2.4e+06 steps; about 20 s of CPU (about 10 s on 2 cores); output about 8 MB".
std::string summary_text(const RunEstimate& e);

}  // namespace lathectl::io
