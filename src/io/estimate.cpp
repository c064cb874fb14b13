#include "lathectl/io/estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

namespace lathectl::io {

RunEstimate report_only() {
  RunEstimate e;
  e.output_bytes = kReportBytes;
  return e;
}

std::string count_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, v >= 1e5 ? "%.2g" : "%.0f", v);
  return b;
}

double estimate_cores() {
  return std::max(1u, std::thread::hardware_concurrency());
}

void add_rig_runs(RunEstimate& e, const Scenario& sc, double runs, double parallel, StepCosts c,
                  double recorded_runs) {
  const double steps = std::ceil(sc.run.duration_s / sc.run.step_s);
  e.simulated_steps += runs * steps;
  const double cpu = runs * steps * c.step_s;
  e.cpu_s += cpu;
  e.wall_s += cpu / std::min({runs, parallel, estimate_cores()});
  e.output_bytes += recorded_runs * (sc.run.duration_s / sc.run.record_interval_s) * c.row_bytes;
  e.breakdown += (e.breakdown.empty() ? "" : "; ") + count_text(runs) +
                 (runs == 1 ? " run" : " runs") + " × " + count_text(steps) + " steps";
}

std::string duration_text(double s, bool upper_bound) {
  const char* q = upper_bound ? "at most" : "about";
  char b[48];
  if (s < 1.0)
    std::snprintf(b, sizeof b, "under a second");
  else if (s < 100.0)
    std::snprintf(b, sizeof b, "%s %.0f s", q, s);
  else if (s < 3600.0)
    std::snprintf(b, sizeof b, "%s %.0f min", q, s / 60.0);
  else if (s < 48.0 * 3600.0)
    std::snprintf(b, sizeof b, "%s %.1f h", q, s / 3600.0);
  else
    std::snprintf(b, sizeof b, "%s %.0f days", q, s / 86400.0);
  return b;
}

std::string size_text(double bytes, bool upper_bound) {
  const char* q = upper_bound ? "at most" : "about";
  char b[48];
  if (bytes < 1e6)
    std::snprintf(b, sizeof b, "%s %.0f kB", q, bytes / 1e3);
  else if (bytes < 1e9)
    std::snprintf(b, sizeof b, "%s %.0f MB", q, bytes / 1e6);
  else
    std::snprintf(b, sizeof b, "%s %.1f GB", q, bytes / 1e9);
  return b;
}

std::string summary_text(const RunEstimate& e) {
  return e.breakdown + "; " + duration_text(e.cpu_s, e.upper_bound) + " of CPU (" +
         duration_text(e.wall_s, e.upper_bound) + " on " + count_text(estimate_cores()) +
         " cores); output " + size_text(e.output_bytes, e.upper_bound);
}

}  // namespace lathectl::io
