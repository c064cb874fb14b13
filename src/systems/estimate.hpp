#pragma once
// What a scenario will cost before it runs (`lathectl check`): the simulated steps and parts its
// study runs, the CPU time that takes, and the size of the output set. A model of each study's
// loops (which runs, sweeps and Monte Carlo parts it makes) times a cost per step or per part
// measured on the examples (docs/scenario-reference.md, "What a run costs"); the time is an
// estimate within a factor of about two, the steps and rows are counted exactly where the
// scenario fixes them and as upper bounds where the part decides (E ends when the last pass
// does, C when the template is traced).

#include <string>

#include "lathectl/io/scenario.hpp"

namespace lathectl::systems {

struct RunEstimate {
  double simulated_steps = 0.0;  // rig steps over every run of the study
  double parts = 0.0;            // Monte Carlo parts (system D), linearised and full model
  double cpu_s = 0.0;            // CPU time on one core of the reference machine
  double wall_s = 0.0;           // on this machine's cores, as the study spreads its runs
  double output_bytes = 0.0;     // the output set: channels CSVs and the report
  std::string breakdown;         // "3 runs × 1.2e+06 steps" …
  bool upper_bound = false;      // E: every run may end sooner (with the part)
};

RunEstimate estimate(const io::Scenario& sc);

// "about 3 min", "about 2.1 h" ("at most …" with upper_bound); "about 1.5 GB".
std::string duration_text(double seconds, bool upper_bound = false);
std::string size_text(double bytes, bool upper_bound = false);
// One line: "2 runs × 2.4e+06 steps; about 20 s of CPU (about 10 s on 2 cores); output about 8 MB".
std::string summary_text(const RunEstimate& e);

}  // namespace lathectl::systems
