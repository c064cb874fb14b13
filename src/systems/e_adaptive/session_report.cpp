// `lathectl report LOG` of the operation log lathectl_oplog writes on LinuxCNC (operations.json,
// or scripts/linuxcnc-sim --out DIR): the registry's session report for system E (entry.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/format.hpp"
#include "lathectl/io/operation_log.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/e_adaptive/entry.hpp"

namespace lathectl::systems::e_adaptive {
namespace {

namespace fs = std::filesystem;
using io::fixed;

// The recording of scripts/linuxcnc-sim, the columns the plots need: read by the reader
// `lathectl compare` uses (io::read_channels_csv, fuzzed); absent, or a recording without these
// columns: no plots. A recording that is there but malformed is an error naming its line.
struct Signals {
  std::vector<double> t, load, limit, feed, line;
};
bool read_signals(const fs::path& csv, Signals& s) {
  std::error_code ec;
  if (!fs::exists(csv, ec)) return false;
  const io::ChannelTable table = io::read_channels_csv(csv);
  auto col = [&](const char* name) -> const std::vector<double>* {
    for (std::size_t i = 0; i < table.names.size(); ++i)
      if (table.names[i] == name) return &table.columns[i];
    return nullptr;
  };
  const auto *t = col("time_s"), *load = col("load"), *limit = col("limit"),
             *feed = col("adaptive_feed"), *line = col("program_line");
  if (!t || !load || !limit || !feed || !line || t->empty()) return false;
  s = {*t, *load, *limit, *feed, *line};
  return true;
}

// With scripts/linuxcnc-sim's recording beside the log: load against the limit (a marker where
// an operation's limit took effect) and the adaptive feed, over time.
void add_recording_plots(io::Report& r, const fs::path& signals, const std::string& unit) {
  Signals s;
  if (read_signals(signals, s)) {
    io::Plot p{"Load against the limit (LinuxCNC recording)",
               "time [s]",
               "load [" + unit + "]",
               {{"load", s.t, s.load, "", false, false}, {"limit", s.t, s.limit, "", true, false}},
               {}};
    for (std::size_t i = 1; i < s.t.size(); ++i)  // where an operation's limit took effect
      if (s.limit[i] != s.limit[i - 1]) p.markers.push_back({s.t[i], fixed(s.limit[i], 0)});
    r.plots.push_back(p);
    r.plots.push_back({"Adaptive feed (motion.adaptive-feed)",
                       "time [s]",
                       "factor of the program's",
                       {{"adaptive feed", s.t, s.feed, "", false, false}},
                       {}});
  }
}

// The operations as the log is read (io::read_operation_log streams them): the first kTableRows
// in the table, every one in the totals and in the plot over the program's lines (every one
// while there are at most kExactRows, else a bounded min/max pyramid per series, as `lathectl
// compare` plots a long channels.csv), so memory does not grow with the log (issue 49).
class Operations {
 public:
  static constexpr std::size_t kTableRows = 1000;
  static constexpr std::size_t kExactRows = sim::Recorder::kPlotValuesPerLevel;
  Operations() : exact_(channels(), kExactRows), streamed_(sim::Recorder::streamed(channels())) {}

  void add(const io::OperationLog::Operation& o) {
    const double pct = o.limit > 0.0 ? o.load_peak / o.limit : 0.0;
    if (table_.size() < kTableRows)
      table_.push_back({fixed(o.line, 0), std::to_string(o.tool), fixed(o.operation, 0), o.mode,
                        fixed(o.limit, 1), fixed(o.load_mean, 1), fixed(o.load_peak, 1),
                        fixed(100.0 * pct, 1) + " %", fixed(o.feed_min, 3), fixed(o.feed_mean, 3),
                        fixed(o.time_in_cut_s, 2), o.reasons, o.alarm});
    ++count_;
    t_cut_ += o.time_in_cut_s;
    if (o.time_in_cut_s > 0.0) worst_ = std::max(worst_, pct);
    alarms_ += o.alarm.empty() ? 0 : 1;
    ++tools_[o.tool];  // (a whole number ≥ 0: read_operation_log checks)
    const double row[] = {o.line, o.limit, o.load_mean, o.load_peak};
    exact_.push_row(row);
    streamed_.push_row(row);
  }
  std::size_t count() const { return count_; }
  std::size_t tools() const { return tools_.size(); }
  double time_in_cut() const { return t_cut_; }
  double worst() const { return worst_; }  // the highest peak / limit of a line in the cut
  int alarms() const { return alarms_; }
  std::vector<std::vector<std::string>>& table() { return table_; }
  // Channel c (1 limit, 2 load mean, 3 peak) against the line: every row, or the pyramid's.
  io::Series series(std::size_t c, std::string name, bool dashed) const {
    io::Series s;
    if (exact_.dropped() > 0) {
      s = io::recorded_series(streamed_, exact_.channels()[c].name.c_str(), std::move(name), "",
                              dashed);
    } else {
      s = {std::move(name), {}, {}, "", dashed, true};
      const auto x = exact_.column(std::size_t{0}), y = exact_.column(c);
      s.x.assign(x.begin(), x.end());
      s.y.assign(y.begin(), y.end());
    }
    s.points = true;
    return s;
  }

 private:
  static std::vector<sim::Channel> channels() {
    return {{"line", ""}, {"limit", ""}, {"load_mean", ""}, {"load_peak", ""}};
  }
  std::vector<std::vector<std::string>> table_;
  std::size_t count_ = 0;
  double t_cut_ = 0.0, worst_ = 0.0;
  int alarms_ = 0;
  std::map<int, int> tools_;
  sim::Recorder exact_, streamed_;
};

}  // namespace

// Any other path: an operation log, or the directory holding it (the registry asks B's and D's
// first, as it lists them).
bool is_session(const fs::path&) {
  return true;
}

int session_report(const fs::path& path, const std::string& out_arg) {
  fs::path log = path;
  if (fs::is_directory(log)) log /= "operations.json";
  if (!fs::exists(log)) throw io::InputError(log.string() + ": no such operation log");
  // Where the report goes, checked before anything is read: never over a device (/dev/null), a
  // directory, the log itself or a file lathectl did not write.
  const fs::path out = out_arg.empty() ? log.parent_path() / "report.html" : fs::path(out_arg);
  const fs::path signals = log.parent_path() / "signals.csv";
  io::check_output_file(out, "--out", {log, signals});
  Operations ops_read;
  const io::OperationLog oplog =
      io::read_operation_log(log, [&](const io::OperationLog::Operation& o) { ops_read.add(o); });
  const std::string file = log.string();
  const std::string& unit = oplog.unit;

  io::Report r;
  r.title = "Operation log";
  r.subtitle = oplog.program.empty() ? file : oplog.program + " · " + file;
  r.description =
      "One row per program line with feed moves, as lathectl_adaptive closed it on LinuxCNC and "
      "lathectl_oplog logged it: the limit in effect, the load's per-revolution mean (mean and "
      "peak over the line), the adaptive feed factor (minimum and mean in the cut), the time in "
      "cut, the controller's reasons and the first alarm. Load in " +
      std::string(unit == "N" ? "N (the force sensor)"
                              : "W (cutting power: spindle drive power "
                                "minus the learned idle power)") +
      ".";
  r.doc_page = "linuxcnc.md";
  io::Table ops{"Operations",
                {"line", "tool", "operation", "mode", "limit [" + unit + "]",
                 "load mean [" + unit + "]", "peak per rev [" + unit + "]", "peak / limit",
                 "feed min", "feed mean", "in cut [s]", "reasons", "alarm"},
                std::move(ops_read.table())};
  const double worst = ops_read.worst();
  r.metrics = {{"operations (lines with feed moves)", std::to_string(ops_read.count())},
               {"tools", std::to_string(ops_read.tools())},
               {"time in cut", fixed(ops_read.time_in_cut(), 2) + " s"},
               {"highest peak per revolution / limit", fixed(100.0 * worst, 1) + " %"},
               {"alarms", std::to_string(ops_read.alarms())}};
  if (oplog.missed_rows > 0)
    r.metrics.emplace_back("operations not logged (shorter than the log's poll)",
                           fixed(oplog.missed_rows, 0));
  r.tables.push_back(ops);
  if (ops_read.count() > ops.rows.size())  // the table's cut, one line below it
    r.tables.push_back({"",
                        {},
                        {{"… " + std::to_string(ops_read.count() - ops.rows.size()) +
                          " more operations: see operations.csv / the log"}}});
  if (!oplog.taught.empty()) {
    io::Table t{"Taught references", {"tool", "operation", "reference", "unit"}, {}};
    for (const auto& e : oplog.taught)
      t.rows.push_back({fixed(e.tool, 0), fixed(e.operation, 0), fixed(e.reference, 1), e.unit});
    r.tables.push_back(t);
  }
  for (const auto& m : oplog.messages) r.notes.push_back(fixed(m.time_s, 2) + " s: " + m.text);
  r.plots.push_back(
      {"Load per program line",
       "program line",
       "load [" + unit + "]",
       {ops_read.series(1, "limit", true), ops_read.series(2, "load mean per line", false),
        ops_read.series(3, "peak per revolution", false)},
       {}});
  add_recording_plots(r, signals, unit);
  io::write_output_file(out, io::render_html(r), "--out", {log, signals});
  std::cout << ops_read.count() << " operations, " << ops_read.tools() << " tools, peak "
            << fixed(100.0 * worst, 1) << " % of the limit → " << out.string() << "\n";
  return 0;
}

}  // namespace lathectl::systems::e_adaptive
