#pragma once
// What a run's verdict says, in two parts kept apart:
// - acceptance, in the user's terms: the scenario's [acceptance] criteria (or its system's
//   defaults, acceptance.hpp), the alarms its controller raised and the parts it did not finish.
//   This is `ok()`, what `--strict` (exit 3) decides on, the ✔/✘ of the console line, of the
//   report's first section and of the demo's index;
// - model checks: the seed documents' claims (summary["claims"]), which say whether the model
//   reproduces the document's statements. They are reported beside it and judge no part.
// Read from the run's summary.json (so every system is judged the same way).

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/io/acceptance.hpp"

namespace lathectl::io {

// A study's acceptance criteria judged on its run: summary.json's "acceptance".
class Acceptance {
 public:
  explicit Acceptance(const AcceptanceLimits& limits) : limits_(limits) {}
  // Judges `key`'s criterion on `value`, in the key's unit (NaN: no value, which meets no
  // limit). A criterion whose limit is 0 (not judged) adds nothing. Returns met.
  bool judge(std::string_view key, double value);
  // {"ok", "criteria": [{"key", "criterion", "value", "limit", "comparison", "unit", "source"
  // ("scenario" or "default"), "met"}]}
  [[nodiscard]] nlohmann::json json() const;

 private:
  const AcceptanceLimits& limits_;
  nlohmann::json criteria_ = nlohmann::json::array();
};

struct Verdict {
  struct Unmet {
    std::size_t index = 0;  // position in summary["claims"]; its report anchor is claim-<index>
    std::string text;
  };
  struct Criterion {
    std::string text;  // "Cpk of the finished sizes 1.1 (limit ≥ 1.33, default)"
    bool met = false;
  };
  std::vector<Criterion> criteria;      // acceptance criteria judged
  std::vector<std::string> alarms;      // "sensor_fault (code 5) at 1.2 s", main run
  std::vector<std::string> unfinished;  // labels of the runs whose part was not finished
  std::size_t claims = 0;               // model checks the run answered
  std::vector<Unmet> unmet;             // those not met

  // Accepted: every criterion met, no alarm, every part finished (the model checks aside).
  [[nodiscard]] bool ok() const;
  [[nodiscard]] std::size_t criteria_met() const;
  [[nodiscard]] bool model_checks_ok() const { return unmet.empty(); }
  // "✔ 2 of 2 acceptance criteria met · model checks: 5 of 6 met (not met: a)" or "✘ 1 of 2
  // acceptance criteria not met: Cpk … · alarm … · part not finished (…) · model checks: …".
  // names = false: without the criteria's, claims' names and the alarms' details, for headings
  // above a list of them.
  [[nodiscard]] std::string line(bool names = true) const;
  // The acceptance part of line() alone; the model checks' part alone ("" without any).
  [[nodiscard]] std::string acceptance_line(bool names = true) const;
  [[nodiscard]] std::string model_checks_line(bool names = true) const;
  // For summary.json: {"ok", "criteria", "criteria_met", "unmet_criteria", "alarms",
  // "unfinished", "model_checks_ok", "claims", "claims_met", "unmet_claims"}.
  [[nodiscard]] nlohmann::json json() const;
};

// The verdict of a summary.json: summary["acceptance"]["criteria"][i]["met"],
// summary["metrics"]["alarms"], summary["metrics"]["finished"] and those of
// summary["comparisons"][i]["metrics"]; the model checks from summary["claims"][i]["met"].
Verdict verdict_of(const nlohmann::json& summary);

// A claim's text up to its first " (" after the run's label and colon — its console-line name.
std::string claim_name(const std::string& text);
// An acceptance criterion of summary.json as a line: "Cpk of the finished sizes 1.1 (limit
// ≥ 1.33, default)".
std::string criterion_text(const nlohmann::json& criterion);

}  // namespace lathectl::io
