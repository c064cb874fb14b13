#pragma once
// What every system's study (src/systems/<folder>/study.cpp) is made of: the phases it goes
// through (Study), and the small pieces it uses to turn runs into a summary and a report: number
// formatting (format.hpp), JSON numbers without NaN, recorded columns, alarm lists, and the claims
// list (each claim with its number and whether it was met).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lathectl/io/format.hpp"  // fmt
#include "lathectl/io/report.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sim/metrics.hpp"
#include "lathectl/sim/recorder.hpp"

namespace lathectl::io {

// A JSON number, or null when not finite (JSON has no NaN).
nlohmann::json json_number(double v);
// A copy of one recorded channel.
std::vector<double> column(const sim::Recorder& rec, const char* name);
// One recorded channel against time for a plot: every row (columns), or at most 4096 points of
// a streamed recorder's pyramid with the pyramid itself for the zoomable chart.
Series recorded_series(const sim::Recorder& rec, const char* channel, std::string name,
                       std::string color, bool dashed = false);
// [{time_s, code, reason}, ...]
nlohmann::json alarms_json(const std::vector<sim::AlarmEvent>& alarms);

// Claims a run answers: the JSON list for summary.json and the report's notes, kept together.
// How a claim's value is judged against its threshold.
// ≤  <  ≥  >  |v| ≤ t  |v| > t  |v − 1| ≤ t (a ratio against its prediction)
enum class Compare { AtMost, Below, AtLeast, Above, Within, Outside, RatioWithin };
const char* compare_symbol(Compare c);

class Claims {
 public:
  // A claim with its threshold as data: met = value <cmp> threshold, and summary.json carries
  // {claim, value, threshold, comparison, met}, so the text, the report and a test that reads the
  // summary cannot disagree on the number. Returns met.
  bool check(const std::string& text, double value, Compare cmp, double threshold);
  // A claim judged by more than one number (met given): prefer check() where one threshold does.
  void add(const std::string& text, double value, bool met);
  void note(const std::string& text) {
    notes_.push_back(text);
    ids_.emplace_back();
  }
  [[nodiscard]] const nlohmann::json& json() const { return json_; }
  [[nodiscard]] const std::vector<std::string>& notes() const { return notes_; }
  // Parallel to notes(): "claim-<i>" for the i-th claim (its index in json()), "" for a note;
  // the report's anchors, which the demo's index links to.
  [[nodiscard]] const std::vector<std::string>& note_ids() const { return ids_; }

 private:
  nlohmann::json json_ = nlohmann::json::array();
  std::vector<std::string> notes_;
  std::vector<std::string> ids_;
};

// A system's study: one scenario's runs turned into summary.json, the report and the result files,
// in named phases. A system derives from it, keeps what the phases share as members, and its
// run() is `return MyStudy(sc).run();`. run() calls the phases in this order:
// While a SummaryOnly lives on this thread, Study::run() leaves out the report phase (5: the
// plots, tables and metrics only report.html shows): for a caller that keeps summary.json alone,
// such as a sweep's case (docs/sweep.md). The summary, the channels and the headline are the
// same: the report phase reads the study's runs, it changes nothing in them.
class SummaryOnly {
 public:
  SummaryOnly();
  ~SummaryOnly();
  SummaryOnly(const SummaryOnly&) = delete;
  SummaryOnly& operator=(const SummaryOnly&) = delete;
  [[nodiscard]] static bool active();
};

class Study {
 public:
  explicit Study(const Scenario& sc) : sc_(sc) {}
  Study(const Study&) = delete;
  Study& operator=(const Study&) = delete;
  virtual ~Study() = default;
  RunOutput run();

 protected:
  // 1. The controllers on the rig: the scenario's run, its comparison, sweeps of the same rig.
  virtual void run_controllers() = 0;
  // 2. The claims the runs answer, each with its number.
  virtual void check_claims(Claims& claims) = 0;
  // 3. Each study beside the runs: its own summary entry, claims, tables and plots (these follow
  //    the report's own).
  virtual void extra_studies(RunOutput& /*out*/, Claims& /*claims*/) {}
  // 4. summary.json: the metrics, the comparison's, the acceptance (system, scenario and file are
  //    set before, the claims after). An extra study's entries may already be in it.
  virtual void summary(nlohmann::json& s) = 0;
  // 5. The report: title, subtitle, metrics, tables, plots (the claims become its notes after).
  virtual void report(Report& rep) = 0;
  // 6. channels.csv / channels_compare.csv (on disk already when streamed to a stage) and the
  //    one-line headline.
  virtual void finish(RunOutput& out) = 0;

  const Scenario& sc_;
};

}  // namespace lathectl::io
