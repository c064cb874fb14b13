#pragma once
// What went wrong in a run, if anything: the claims it did not meet, the alarms its controller
// raised and the parts it did not finish. Read from the run's summary.json (so every system is
// judged the same way), printed at the end of its console line, shown at the top of its report
// and in the demo's index, and decided on by `--strict` (exit 3).

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace lathectl::io {

struct Verdict {
  struct Unmet {
    std::size_t index = 0;  // position in summary["claims"]; its report anchor is claim-<index>
    std::string text;
  };
  std::size_t claims = 0;         // claims the run answered
  std::vector<Unmet> unmet;       // those not met
  std::vector<std::string> alarms;      // "sensor_fault (code 5) at 1.2 s", main run
  std::vector<std::string> unfinished;  // labels of the runs whose part was not finished

  [[nodiscard]] bool ok() const { return unmet.empty() && alarms.empty() && unfinished.empty(); }
  // "✔ 5 of 5 claims met" or "✘ 2 of 5 claims not met: a; b · alarm … · part not finished (…)".
  // names = false: without the claims' names and the alarms' details ("✘ 2 of 5 claims not met
  // · 1 alarm · part not finished"), for headings above a list of them.
  [[nodiscard]] std::string line(bool names = true) const;
  // {"ok", "claims", "claims_met", "unmet_claims", "alarms", "unfinished"} for summary.json.
  [[nodiscard]] nlohmann::json json() const;
};

// The verdict of a summary.json: summary["claims"][i]["met"], summary["metrics"]["alarms"],
// summary["metrics"]["finished"] and those of summary["comparisons"][i]["metrics"].
Verdict verdict_of(const nlohmann::json& summary);

// A claim's text up to its first " (" after the run's label and colon — its console-line name.
std::string claim_name(const std::string& text);

}  // namespace lathectl::io
