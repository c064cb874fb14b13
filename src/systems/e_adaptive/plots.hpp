#pragma once
// System E's time-series plots: the controllers compared along the cut, and the main run's
// detail (force within the revolution, disturbances, the reason-code timeline).

#include <string>
#include <vector>

#include "lathectl/io/report.hpp"
#include "systems/e_adaptive/metrics.hpp"

namespace lathectl::systems::e_adaptive {

struct PlotRun {
  const sim::Recorder* rec = nullptr;
  const sim::MetricsE* m = nullptr;
  std::string label;
  bool speed_law = false;  // seed 004's V_opt is recorded
};

// Appends the plots; runs.front() is the main run, `mk` its events on its time axis.
void add_run_plots(io::Report& rep, const std::vector<PlotRun>& runs,
                   const std::vector<io::Marker>& mk, const std::string& pname,
                   const std::string& unit);

}  // namespace lathectl::systems::e_adaptive
