#pragma once
// Scenario → rig → runner → recorder → report. Runs a scenario (and its comparison and sweep
// runs), computes the metrics that answer its system's claims, and writes summary.json,
// channels.csv (and channels_compare.csv) and report.html into an output directory.

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "lathectl/io/report.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::io {

struct RunOutput {
  nlohmann::json summary;  // {"system", "scenario", "metrics", ...}
  std::string channels_csv;
  std::string compare_csv;  // empty when no comparison
  Report report;
  std::string headline;  // one line for the demo index
};

// Throws InputError (bad scenario) or std::runtime_error (numerical failure: NaN, divergence).
RunOutput run_scenario(const Scenario& sc);
void write_outputs(const RunOutput& out, const std::filesystem::path& dir);

}  // namespace lathectl::io
