// `lathectl report LOG`: the operation log lathectl_oplog writes on LinuxCNC (operations.json,
// one row per program line with feed moves) as the same kind of HTML report as `lathectl run`'s:
// the per-line table, the taught references, the operator messages, and, when the recording of
// scripts/linuxcnc-sim lies beside it (signals.csv), load against limit and the adaptive feed
// over time. A directory of scripts/linuxcnc-sim-gauge's series (summary.json with the parts,
// no operation log) gets the series' report instead, as `lathectl run`'s for system D: the size
// table, Cp/Cpk and the histogram of finished sizes against the tolerance. A directory of
// scripts/linuxcnc-sim-twin's session (system B: summary.json and signals.csv with the chatter
// plant's channels) gets the session's report: its metrics and the vibration, the turrets' feeds
// and the flagged axis's offset over time.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/json_file.hpp"
#include "lathectl/io/operation_log.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"

namespace lathectl::cli {
namespace {

namespace fs = std::filesystem;

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

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

// The histogram of a series' finished sizes: bins of a tenth of the tolerance over ±1.5
// tolerances (the limits inside), wider when a size lies beyond; the normal law of the series' own
// mean and σ.
io::Plot size_histogram(const std::vector<double>& sizes, double tol, double mean, double sigma) {
  double lo = -1.5 * tol, hi = 1.5 * tol;
  for (double e : sizes) {
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  const double w = 0.1 * tol;
  const auto bins = static_cast<std::size_t>(std::ceil((hi - lo) / w)) + 1;
  std::vector<double> counts(bins, 0.0);
  for (double e : sizes) counts[static_cast<std::size_t>((e - lo) / w)] += 1.0;
  io::Series hist{"finished sizes (" + std::to_string(sizes.size()) + " parts)", {}, {},
                  "#1f77b4", false, false};
  for (std::size_t b = 0; b < bins; ++b) {
    const double x0 = lo + static_cast<double>(b) * w;
    hist.x.insert(hist.x.end(), {x0, x0 + w});
    hist.y.insert(hist.y.end(), {counts[b], counts[b]});
  }
  io::Plot h{"Finished sizes: finished − target",
             "finished − target [µm]",
             "parts per bin",
             {hist},
             {{0.0, "target"}, {-tol, "LSL"}, {tol, "USL"}}};
  if (sigma > 0.0) {
    io::Series normal{"normal, the series' mean and σ", {}, {}, "#d62728", true, false};
    for (int k = 0; k <= 200; ++k) {
      const double x = lo + (hi + w - lo) * k / 200.0, z = (x - mean) / sigma;
      normal.x.push_back(x);
      normal.y.push_back(static_cast<double>(sizes.size()) * w /
                         (sigma * std::sqrt(2.0 * std::numbers::pi)) *
                         std::exp(-0.5 * z * z));
    }
    h.series.push_back(normal);
  }
  return h;
}

// System D's series on LinuxCNC (scripts/linuxcnc-sim-gauge's summary.json): every number read
// is checked (JsonFile names the file, line and key of a bad one).
int gauge_series_report(const fs::path& summary, const std::string& out_arg) {
  const fs::path out =
      out_arg.empty() ? summary.parent_path() / "report.html" : fs::path(out_arg);
  io::check_output_file(out, "--out", {summary});
  const io::JsonFile f = io::JsonFile::read(summary, "the series' summary");
  const auto& doc = f.doc();
  if (!doc.is_object() || !doc.contains("metrics") || !doc["metrics"].is_object())
    f.fail("metrics", "expected the series' metrics");
  const auto& m = doc["metrics"];
  const auto num = [&](const char* k) { return f.number(m, "metrics", k); };
  const double tol = num("tolerance_um"), mean = num("size_mean_error_um");
  if (!doc.contains("parts_detail") || !doc["parts_detail"].is_array())
    f.fail("parts_detail", "expected the parts, one object each");
  const auto& parts = doc["parts_detail"];
  io::Report r;
  r.title = "System D on LinuxCNC — a series of parts";
  r.subtitle = (doc.contains("program") && doc["program"].is_string()
                    ? doc["program"].get<std::string>() + " · "
                    : std::string()) +
               summary.string();
  r.description =
      "Each part loaded, the gauge re-armed and one G38.3 plunge ended at size by lathectl_gauge "
      "(motion.probe-input), its steps changing the feed through motion.adaptive-feed. Sizes are "
      "the plant's finished size − target; the limits target ± tolerance_um.";
  r.doc_page = "linuxcnc.md";
  const double n_parts = num("parts");
  r.metrics = {{"parts", fixed(n_parts, 0)},
               {"mean finished size − target [µm]", fixed(mean, 3)},
               {"σ of finished size [µm]", fixed(num("size_sigma_um"), 3)},
               {"Cp", fixed(num("cp"), 2)},
               {"Cpk", fixed(num("cpk"), 2)},
               {"tolerance ± [µm]", fixed(tol, 1)},
               {"backstop (limit position) [µm]", fixed(num("backstop_um"), 1)},
               {"cuts ended by the backstop", fixed(num("backstop_trips"), 0)},
               {"threshold S_th [V]", fixed(num("threshold_V"), 4)}};
  if (m.contains("trip_to_stop_s_max"))
    r.metrics.emplace_back("threshold's crossing to the infeed's standstill, largest [ms]",
                           fixed(1e3 * num("trip_to_stop_s_max"), 1));
  io::Table t{"Finished sizes", {"part", "finished − target [µm]", "steps: size at each [µm]",
                                 "crossing to standstill [ms]", "ended by", "alarm"}, {}};
  std::vector<double> sizes;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const auto& p = parts[i];
    const std::string key = io::JsonFile::element("parts_detail", i);
    if (!p.is_object()) f.fail(key, "expected a part");
    const double e = f.number(p, key, "error_um");
    sizes.push_back(e);
    std::string steps;
    if (p.contains("steps") && p["steps"].is_array())
      for (std::size_t j = 0; j < p["steps"].size(); ++j)
        steps += (j ? ", " : "") +
                 fixed(f.number(p["steps"][j], io::JsonFile::element(key + ".steps", j),
                                "size_um"),
                       2);
    const bool backstop = p.contains("backstop") && p["backstop"].is_boolean() &&
                          p["backstop"].get<bool>();
    const bool alarm = p.contains("alarm") && p["alarm"].is_boolean() && p["alarm"].get<bool>();
    t.rows.push_back({fixed(f.number(p, key, "part"), 0), fixed(e, 2), steps,
                      p.contains("trip_to_stop_s") && p["trip_to_stop_s"].is_number()
                          ? fixed(1e3 * p["trip_to_stop_s"].get<double>(), 1)
                          : "",
                      backstop ? "backstop" : "size", alarm ? "yes" : ""});
  }
  const double sigma = num("size_sigma_um");
  r.plots.push_back(size_histogram(sizes, tol, mean, sigma));
  r.tables.push_back(t);
  r.plots_first = true;  // the histogram above the long size table
  io::write_output_file(out, io::render_html(r), "--out", {summary});
  std::cout << sizes.size() << " parts: mean " << fixed(mean, 3) << " µm, σ " << fixed(sigma, 3)
            << " µm, Cpk " << fixed(num("cpk"), 2) << " → " << out.string() << "\n";
  return 0;
}

// A measure of a session's summary.json it reached, else "—": `path` is dotted, its numbers
// checked.
std::string measure(const io::JsonFile& f, const std::string& path, double scale, int digits) {
  const auto& doc = f.doc();
  const nlohmann::json* v = &doc;
  std::string key;
  std::size_t a = 0;
  while (a <= path.size()) {
    const std::size_t b = std::min(path.find('.', a), path.size());
    const std::string name = path.substr(a, b - a);
    if (!v->is_object() || !v->contains(name) || (*v)[name].is_null()) return "—";
    if (b == path.size()) return fixed(scale * f.number(*v, key, name.c_str()), digits);
    key += (key.empty() ? "" : ".") + name;
    v = &(*v)[name];
    a = b + 1;
  }
  return "—";
}

// System B's session's metrics: the module's plan and engagement, the amplitudes with and
// without it, the feeds, the external offset.
std::vector<std::pair<std::string, std::string>> twin_metrics(const io::JsonFile& f) {
  const auto val = [&](const std::string& path, double scale, int digits) {
    return measure(f, path, scale, digits);
  };
  return {
      {"module engaged after contact [s]", val("modulation.engaged_after_contact_s", 1, 3)},
      {"plan S_min / ΔS [mm/min]", val("modulation.S_min_mm_per_min", 1, 1) + " / " +
                                       val("modulation.dS_mm_per_min", 1, 1)},
      {"plan Δl [mm] / n_s", val("modulation.dl_mm", 1, 3) + " / " + val("modulation.n_s", 1, 0)},
      {"chatter frequency (detector 20) [Hz]", val("chatter_frequency_Hz", 1, 1)},
      {"amplitude with the module, 2–3 s after engaging [µm]",
       val("vibration_amplitude_um.with", 1, 2)},
      {"amplitude without (the module off, the cut's end) [µm]",
       val("vibration_amplitude_um.without", 1, 2)},
      {"growth rate before engaging / module off [1/s]",
       val("growth_rate_per_s.before_engaging", 1, 3) + " / " +
           val("growth_rate_per_s.module_off", 1, 3)},
      {"mean feed programmed / left / right [mm/min]",
       val("mean_feed_mm_per_min.programmed", 1, 2) + " / " +
           val("mean_feed_mm_per_min.left", 1, 2) + " / " +
           val("mean_feed_mm_per_min.right", 1, 2)},
      {"left turret off the right one's plan, largest [µm]",
       val("left_turret_max_gap_to_plan_mm", 1e3, 3)},
      {"feed step → axis speed, median / longest [ms]",
       val("eoffset.latency_ms.median", 1, 0) + " / " + val("eoffset.latency_ms.max", 1, 0)},
      {"offset, largest / after the program [mm]",
       val("eoffset.max_abs_mm", 1, 4) + " / " + val("eoffset.at_end_mm", 1, 6)},
      {"override: factor / left turret [mm/min]",
       val("override.factor", 1, 3) + " / " + val("override.left_mm_per_min", 1, 2)},
      {"programmed variant: the named turret on its level [share]",
       val("programmed.left_on_level_share", 1, 3)}};
}

// System B's session on the twin-turret lathe (scripts/linuxcnc-sim-twin): summary.json's measures
// (null where the session did not reach them) and the recording's channels.
int twin_session_report(const fs::path& dir, const std::string& out_arg) {
  const fs::path summary = dir / "summary.json", csv = dir / "signals.csv";
  const fs::path out = out_arg.empty() ? dir / "report.html" : fs::path(out_arg);
  io::check_output_file(out, "--out", {summary, csv});
  const io::JsonFile f = io::JsonFile::read(summary, "the session's summary");
  const auto& doc = f.doc();
  if (!doc.is_object()) f.fail("", "expected the session's summary (an object)");
  const auto val = [&](const std::string& path, double scale, int digits) {
    return measure(f, path, scale, digits);
  };
  io::Report r;
  r.title = "System B on LinuxCNC — the twin-turret lathe";
  r.subtitle = (doc.contains("program") && doc["program"].is_string()
                    ? doc["program"].get<std::string>() + " · "
                    : std::string()) +
               summary.string();
  r.description =
      "The left turret on X/Z, the right one on U/W, one program for both; lathectl_chatter cuts "
      "the slender part with both tools and lathectl_modfeed modulates the flagged turret's feed "
      "through LinuxCNC's external axis offset on its axial axis. Amplitudes are rig B's measure "
      "(the peak of the high-passed displacement at the tool).";
  r.doc_page = "linuxcnc.md";
  r.metrics = twin_metrics(f);
  const io::ChannelTable table = io::read_channels_csv(csv);
  auto col = [&](const char* name) -> const std::vector<double>& {
    for (std::size_t i = 0; i < table.names.size(); ++i)
      if (table.names[i] == name) return table.columns[i];
    throw io::InputError(csv.string() + ": no column " + name + " (not linuxcnc-sim-twin's)");
  };
  const auto &t = col("time_s"), &peak = col("vibration_peak_um"), &a0 = col("a0_um");
  const auto &z = col("z_mm"), &w = col("w_mm"), &level = col("feed_mm_per_min");
  const auto &eo = col("w_eoffset_mm"), &motion = col("motion_type"), &on = col("module_on");
  std::vector<io::Marker> marks;
  for (const auto& [key, label] :
       {std::pair{"contact_at_s", "contact"}, {"modulation.engaged_at_s", "engaged"},
        {"cut_end_s", "the cut's end"}}) {
    const std::string v = val(key, 1, 3);
    if (v != "—") marks.push_back({std::stod(v), label});
  }
  r.plots.push_back({"Vibration at the tool", "time [s]", "amplitude [µm]",
                     {{"peak of the high-passed displacement", t, peak, "", false, false},
                      {"a0 (ADC 19, 0 below the dead zone)", t, a0, "", true, false}},
                     marks});
  // The turrets' speeds from the recorded joints (one servo period apart), in feed moves.
  std::vector<double> vz(t.size(), 0.0), vw(t.size(), 0.0), s_level(t.size(), 0.0);
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double dt = t[i] - t[i - 1];
    if (dt <= 0.0 || (motion[i] != 2.0 && motion[i] != 3.0)) continue;
    s_level[i] = on[i] != 0.0 ? level[i] : 0.0;
    vz[i] = std::abs(z[i] - z[i - 1]) / dt * 60.0;
    vw[i] = std::abs(w[i] - w[i - 1]) / dt * 60.0;
  }
  r.plots.push_back({"The turrets' feeds", "time [s]", "feed [mm/min]",
                     {{"right turret (W)", t, vw, "", false, false},
                      {"left turret (Z)", t, vz, "", false, false},
                      {"the module's level S(t) (while on)", t, s_level, "", true, false}},
                     marks});
  r.plots.push_back({"W's external offset (axis.w.eoffset)", "time [s]", "offset [mm]",
                     {{"offset", t, eo, "", false, false}},
                     marks});
  io::write_output_file(out, io::render_html(r), "--out", {summary, csv});
  std::cout << "system B session: " << t.size() << " servo periods → " << out.string() << "\n";
  return 0;
}

int oplog_report(fs::path log, const std::string& out_arg);

int report(const std::string& log_arg, const std::string& out_arg) {
  fs::path log = log_arg;
  // scripts/linuxcnc-sim-twin's directory: the session's report.
  {
    const fs::path dir = fs::is_directory(log) ? log : log.parent_path();
    std::error_code ec;
    if ((fs::is_directory(log) || log.filename() == "summary.json") &&
        !fs::exists(dir / "operations.json", ec) && fs::exists(dir / "summary.json", ec) &&
        fs::exists(dir / "signals.csv", ec) && fs::exists(dir / "report.txt", ec))
      return twin_session_report(dir, out_arg);
  }
  // scripts/linuxcnc-sim-gauge's directory (or its summary.json): the series' report.
  {
    const fs::path dir = fs::is_directory(log) ? log : log.parent_path();
    std::error_code ec;
    const bool gauge = (fs::is_directory(log) || log.filename() == "summary.json") &&
                       !fs::exists(dir / "operations.json", ec) &&
                       fs::exists(dir / "summary.json", ec) && fs::exists(dir / "parts.csv", ec);
    if (gauge) return gauge_series_report(dir / "summary.json", out_arg);
  }
  return oplog_report(log, out_arg);
}

// lathectl_oplog's operation log (operations.json), and signals.csv beside it when there.
int oplog_report(fs::path log, const std::string& out_arg) {
  if (fs::is_directory(log)) log /= "operations.json";
  if (!fs::exists(log)) throw io::InputError(log.string() + ": no such operation log");
  // Where the report goes, checked before anything is read: never over a device (/dev/null), a
  // directory, the log itself or a file lathectl did not write.
  const fs::path out = out_arg.empty() ? log.parent_path() / "report.html" : fs::path(out_arg);
  const fs::path signals = log.parent_path() / "signals.csv";
  io::check_output_file(out, "--out", {log, signals});
  const io::OperationLog oplog =
      io::read_operation_log(io::JsonFile::read(log, "the operation log"));
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
      std::string(unit == "N" ? "N (the force sensor)" : "W (cutting power: spindle drive power "
                                                         "minus the learned idle power)") +
      ".";
  r.doc_page = "linuxcnc.md";
  io::Table ops{"Operations", {"line", "tool", "operation", "mode", "limit [" + unit + "]",
                               "load mean [" + unit + "]", "peak per rev [" + unit + "]",
                               "peak / limit", "feed min", "feed mean", "in cut [s]",
                               "reasons", "alarm"}, {}};
  double t_cut = 0.0, worst = 0.0;
  int alarms = 0;
  std::map<int, int> tools;
  io::Series mean_s{"load mean per line", {}, {}, "", false, true};
  io::Series peak_s{"peak per revolution", {}, {}, "", false, true};
  io::Series lim_s{"limit", {}, {}, "", true, true};
  for (const auto& o : oplog.rows) {
    const double line = o.line, limit = o.limit, mean = o.load_mean, peak = o.load_peak;
    const double cut = o.time_in_cut_s;
    const int tool = o.tool;  // (a whole number ≥ 0: read_operation_log checks)
    const std::string& alarm = o.alarm;
    const double pct = limit > 0.0 ? peak / limit : 0.0;
    ops.rows.push_back({fixed(line, 0), std::to_string(tool), fixed(o.operation, 0), o.mode,
                        fixed(limit, 1), fixed(mean, 1), fixed(peak, 1),
                        fixed(100.0 * pct, 1) + " %", fixed(o.feed_min, 3), fixed(o.feed_mean, 3),
                        fixed(cut, 2), o.reasons, alarm});
    t_cut += cut;
    if (cut > 0.0) worst = std::max(worst, pct);
    alarms += alarm.empty() ? 0 : 1;
    ++tools[tool];
    mean_s.x.push_back(line);
    mean_s.y.push_back(mean);
    peak_s.x.push_back(line);
    peak_s.y.push_back(peak);
    lim_s.x.push_back(line);
    lim_s.y.push_back(limit);
  }
  r.metrics = {{"operations (lines with feed moves)", std::to_string(ops.rows.size())},
               {"tools", std::to_string(tools.size())},
               {"time in cut", fixed(t_cut, 2) + " s"},
               {"highest peak per revolution / limit", fixed(100.0 * worst, 1) + " %"},
               {"alarms", std::to_string(alarms)}};
  if (oplog.missed_rows > 0)
    r.metrics.emplace_back("operations not logged (shorter than the log's poll)",
                           fixed(oplog.missed_rows, 0));
  r.tables.push_back(ops);
  if (!oplog.taught.empty()) {
    io::Table t{"Taught references", {"tool", "operation", "reference", "unit"}, {}};
    for (const auto& e : oplog.taught)
      t.rows.push_back({fixed(e.tool, 0), fixed(e.operation, 0), fixed(e.reference, 1), e.unit});
    r.tables.push_back(t);
  }
  for (const auto& m : oplog.messages) r.notes.push_back(fixed(m.time_s, 2) + " s: " + m.text);
  r.plots.push_back({"Load per program line", "program line", "load [" + unit + "]",
                     {lim_s, mean_s, peak_s}, {}});
  Signals s;
  if (read_signals(signals, s)) {
    io::Plot p{"Load against the limit (LinuxCNC recording)", "time [s]", "load [" + unit + "]",
               {{"load", s.t, s.load, "", false, false}, {"limit", s.t, s.limit, "", true, false}},
               {}};
    for (std::size_t i = 1; i < s.t.size(); ++i)  // where an operation's limit took effect
      if (s.limit[i] != s.limit[i - 1]) p.markers.push_back({s.t[i], fixed(s.limit[i], 0)});
    r.plots.push_back(p);
    r.plots.push_back({"Adaptive feed (motion.adaptive-feed)", "time [s]", "factor of the program's",
                       {{"adaptive feed", s.t, s.feed, "", false, false}}, {}});
  }
  io::write_output_file(out, io::render_html(r), "--out", {log, signals});
  std::cout << ops.rows.size() << " operations, " << tools.size() << " tools, peak "
            << fixed(100.0 * worst, 1) << " % of the limit → " << out.string() << "\n";
  return 0;
}

}  // namespace

void add_report(CLI::App& app, Commands& out) {
  struct Args {
    std::string log, out;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "report", "HTML report of a LinuxCNC operation log (lathectl_oplog's operations.json)");
  sub->add_option("log", a->log,
                  "operations.json, or the directory holding it (scripts/linuxcnc-sim --out DIR); a "
                  "system-D series' directory (summary.json and parts.csv): the series' report; a "
                  "system-B session's (summary.json, signals.csv, report.txt): the session's")
      ->required();
  sub->add_option("--out", a->out, "the report (default: report.html beside the log)");
  sub->footer("The operation log and its columns: " + doc("linuxcnc.md") + ".");
  out.push_back({sub, [a] { return report(a->log, a->out); }});
}

}  // namespace lathectl::cli
