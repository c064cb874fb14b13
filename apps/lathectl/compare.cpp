// `lathectl compare RUN_DIR... --out DIR`: two or more runs' output sets side by side — their
// channels overlaid on one axis (the first column of channels.csv: time, or the part number), the
// settings that differ, the metrics with their differences to the first run, and the claims whose
// verdict changed. Writes summary.json and report.html as one output set.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <span>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/format.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/json_file.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/sim/recorder.hpp"

namespace lathectl::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A run's channels as channels.csv is read, row by row: every row while there are at most
// kExactRows (the plots are then built from every sample, as they always were), and a bounded
// min/max pyramid per channel (sim::Recorder::streamed, as `lathectl run` records) for a longer
// run, so compare's memory does not grow with channels.csv (two 700 MB files held as columns ran
// out of memory; issue 49).
class RunChannels final : public io::ChannelRowSink {
 public:
  static constexpr std::size_t kExactRows = sim::Recorder::kPlotValuesPerLevel;
  void header(const std::vector<std::string>& names) override {
    std::vector<sim::Channel> channels;
    for (const std::string& n : names) channels.push_back({n, ""});
    exact_ = sim::Recorder(channels, kExactRows);
    streamed_ = sim::Recorder::streamed(std::move(channels));
  }
  void row(std::span<const double> values) override {
    exact_.push_row(values);
    streamed_.push_row(values);
  }
  [[nodiscard]] const std::vector<sim::Channel>& channels() const { return exact_.channels(); }
  [[nodiscard]] std::size_t rows() const { return streamed_.rows(); }
  // Channel c against channel 0: every sample, or (a longer run) the pyramid and its points.
  [[nodiscard]] io::Series series(std::size_t c, std::string name) const {
    if (exact_.dropped() > 0)
      return io::recorded_series(streamed_, channels()[c].name.c_str(), std::move(name), "");
    io::Series s;
    s.name = std::move(name);
    const auto x = exact_.column(std::size_t{0}), y = exact_.column(c);
    s.x.assign(x.begin(), x.end());
    s.y.assign(y.begin(), y.end());
    return s;
  }

 private:
  sim::Recorder exact_, streamed_;
};

struct Run {
  std::string label;  // the directory as given
  json summary;
  RunChannels channels;
};

Run read_run(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw io::InputError(dir + ": not a directory");
  const fs::path summary = fs::path(dir) / "summary.json";
  const fs::path csv = fs::path(dir) / "channels.csv";
  for (const fs::path& f : {summary, csv})
    if (!fs::is_regular_file(f, ec))
      throw io::InputError(dir + ": not a lathectl run's output (no " +
                           f.filename().string() + ")");
  Run r;
  r.label = dir;
  const io::JsonFile file = io::JsonFile::read(summary, "the run's summary");
  r.summary = file.doc();
  if (!r.summary.is_object()) file.fail("", "expected an object (a run's summary)");
  for (const char* key : {"metrics", "claims"}) {
    const bool metrics = std::string(key) == "metrics";
    const auto it = r.summary.find(key);
    if (it == r.summary.end() || !(metrics ? it->is_object() : it->is_array()))
      file.fail(key, metrics ? "expected an object" : "expected an array");
  }
  io::read_channels_csv(csv, r.channels);
  if (r.channels.rows() == 0)
    throw io::InputError(csv.string() + ": no rows");
  return r;
}

// "a.b.c" → scalar for every scalar leaf of an object (arrays of scalars joined as text).
void flatten(const json& j, const std::string& prefix, std::map<std::string, json>& out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) flatten(v, prefix.empty() ? k : prefix + "." + k, out);
  } else if (!j.is_array()) {
    out[prefix] = j;
  } else if (std::all_of(j.begin(), j.end(), [](const json& e) { return e.is_primitive(); })) {
    out[prefix] = j.dump();
  }
}

std::string text_of(const json& v) {
  if (v.is_null()) return "—";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number()) {
    char b[48];
    std::snprintf(b, sizeof b, "%.6g", v.get<double>());
    return b;
  }
  return v.dump();
}

// "x − first" for numbers (with the relative change when the first is not 0), "" when equal,
// "changed" for other values that differ.
std::string difference(const json& first, const json& v) {
  if (first == v) return "";
  if (first.is_number() && v.is_number()) {
    const double a = first.get<double>(), b = v.get<double>();
    char buf[80];
    if (a != 0.0 && std::isfinite(a) && std::isfinite(b))
      std::snprintf(buf, sizeof buf, "%+.6g (%+.1f %%)", b - a, (b - a) / std::abs(a) * 100.0);
    else
      std::snprintf(buf, sizeof buf, "%+.6g", b - a);
    return buf;
  }
  return "changed";
}

// Rows of "key | run 1 | run 2 … | difference to run 1 (each further run)" over the union of
// the runs' keys; with only_changed, the keys whose value is not the same in every run.
io::Table side_by_side(const std::string& title, const std::vector<Run>& runs,
                       const std::string& section, bool only_changed, json& out) {
  std::vector<std::map<std::string, json>> flat(runs.size());
  std::map<std::string, int> keys;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].summary.contains(section)) flatten(runs[i].summary[section], "", flat[i]);
    for (const auto& kv : flat[i]) keys[kv.first] = 0;
  }
  io::Table t{title, {"key"}, {}};
  for (std::size_t i = 0; i < runs.size(); ++i) t.header.push_back("run " + std::to_string(i + 1));
  for (std::size_t i = 1; i < runs.size(); ++i)
    t.header.push_back("run " + std::to_string(i + 1) + " − run 1");
  out = json::object();
  for (const auto& kv : keys) {
    const std::string& key = kv.first;
    std::vector<json> v(runs.size());
    bool same = true;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto it = flat[i].find(key);
      v[i] = it == flat[i].end() ? json() : it->second;
      same = same && v[i] == v[0];
    }
    if (only_changed && same) continue;
    std::vector<std::string> row{key};
    json values = json::array(), diffs = json::array();
    for (const json& x : v) {
      row.push_back(text_of(x));
      values.push_back(x);
    }
    for (std::size_t i = 1; i < runs.size(); ++i) {
      row.push_back(difference(v[0], v[i]));
      diffs.push_back(v[0].is_number() && v[i].is_number()
                          ? json(v[i].get<double>() - v[0].get<double>())
                          : json(v[0] != v[i]));
    }
    t.rows.push_back(std::move(row));
    out[key] = {{"values", values}, {"differences", diffs}};
  }
  return t;
}

// Claims matched by their text before its first " (" — what follows there quotes the run's own
// numbers ("… (≤ 0.2; 1.46 % against 12.2 %)"); a repeated text by its occurrence. Met / not met
// per run, and whether the verdict changed.
io::Table claims_table(const std::vector<Run>& runs, json& out, std::size_t& changed) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<json>> met;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    std::map<std::string, int> seen;
    for (const json& c : runs[i].summary["claims"]) {
      if (!c.is_object() || !c.contains("claim") || !c["claim"].is_string()) continue;
      const std::string full = c["claim"].get<std::string>();
      std::string text = full.substr(0, full.find(" ("));
      if (const int k = seen[text]++; k > 0) text += " [" + std::to_string(k + 1) + "]";
      auto [it, fresh] = met.try_emplace(text, std::vector<json>(runs.size()));
      if (fresh) order.push_back(text);
      it->second[i] = c.contains("met") ? c["met"] : json();
    }
  }
  io::Table t{"Claims", {"claim"}, {}};
  for (std::size_t i = 0; i < runs.size(); ++i) t.header.push_back("run " + std::to_string(i + 1));
  t.header.push_back("changed");
  out = json::array();
  changed = 0;
  for (const std::string& text : order) {
    const auto& m = met[text];
    std::vector<std::string> row{text};
    bool differs = false;
    for (const json& x : m) {
      row.push_back(x.is_boolean() ? (x.get<bool>() ? "✔ met" : "✘ not met") : "—");
      differs = differs || x != m[0];
    }
    std::string what;
    if (differs) {
      ++changed;
      for (std::size_t i = 1; i < m.size(); ++i)
        if (m[i] != m[0])
          what += (what.empty() ? "" : "; ") + std::string("run ") + std::to_string(i + 1) + ": " +
                  (m[0] == json(true) ? "met" : m[0] == json(false) ? "not met" : "absent") +
                  " → " + (m[i] == json(true) ? "met" : m[i] == json(false) ? "not met" : "absent");
    }
    row.push_back(what);
    t.rows.push_back(std::move(row));
    out.push_back({{"claim", text}, {"met", m}, {"changed", differs}});
  }
  return t;
}

// Series of equal records share one pyramid, so the report holds their data once (as it does for
// series given whole, by their values): a longer run's constant channels.
void share_equal_pyramids(std::vector<io::Plot>& plots) {
  using P = sim::PlotPyramid;
  const auto same = [](const P& a, const P& b) {
    if (a.samples() != b.samples() || a.x0() != b.x0() || a.x_last() != b.x_last() ||
        a.dx() != b.dx() || a.uniform() != b.uniform() || a.levels().size() != b.levels().size())
      return false;
    for (std::size_t i = 0; i < a.levels().size(); ++i)
      if (a.levels()[i].bucket != b.levels()[i].bucket || a.levels()[i].y != b.levels()[i].y ||
          a.levels()[i].x != b.levels()[i].x)
        return false;
    return true;
  };
  std::vector<std::shared_ptr<const P>> kept;
  for (io::Plot& p : plots)
    for (io::Series& s : p.series) {
      if (!s.pyramid) continue;
      const auto it = std::find_if(kept.begin(), kept.end(), [&](const auto& k) {
        return same(*k, *s.pyramid);
      });
      if (it == kept.end())
        kept.push_back(s.pyramid);
      else
        s.pyramid = *it;
    }
}

// One plot per channel: the runs overlaid on the first column (time or part number).
std::vector<io::Plot> channel_plots(const std::vector<Run>& runs) {
  std::vector<std::string> order;
  for (const Run& r : runs)
    for (std::size_t c = 1; c < r.channels.channels().size(); ++c)
      if (std::find(order.begin(), order.end(), r.channels.channels()[c].name) == order.end())
        order.push_back(r.channels.channels()[c].name);
  std::vector<io::Plot> plots;
  for (const std::string& name : order) {
    io::Plot p;
    p.title = name;
    p.y_label = name;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto& ch = runs[i].channels.channels();
      const auto at = std::find_if(ch.begin(), ch.end(),
                                   [&](const sim::Channel& c) { return c.name == name; });
      if (at == ch.end()) continue;
      if (p.x_label.empty()) p.x_label = ch[0].name == "time_s" ? "time [s]" : ch[0].name;
      p.series.push_back(runs[i].channels.series(static_cast<std::size_t>(at - ch.begin()),
                                                 "run " + std::to_string(i + 1)));
      p.series.back().points = ch[0].name != "time_s";
    }
    plots.push_back(std::move(p));
  }
  share_equal_pyramids(plots);
  return plots;
}

int compare(const std::vector<std::string>& dirs, const std::string& out) {
  if (dirs.size() < 2) throw io::InputError("compare: give two or more run directories");
  std::error_code ec;
  for (const std::string& d : dirs)
    if (fs::exists(out, ec) && fs::equivalent(d, out, ec))
      throw io::InputError("--out " + out + ": is one of the runs compared; choose another");
  std::vector<Run> runs;
  for (const std::string& d : dirs) runs.push_back(read_run(d));
  // Runs of different systems share no claims and hardly a metric or channel: a comparison of them
  // would be a page of "—". Say so instead.
  auto system_of = [](const Run& r) {
    const auto it = r.summary.find("system");
    return it != r.summary.end() && it->is_string() ? it->get<std::string>() : std::string("?");
  };
  for (std::size_t i = 1; i < runs.size(); ++i)
    if (system_of(runs[i]) != system_of(runs[0]))
      throw io::InputError("compare: " + runs[0].label + " is a run of system " +
                           system_of(runs[0]) + ", " + runs[i].label + " of system " +
                           system_of(runs[i]) +
                           ": compare runs of one system (the same claims, metrics and channels)");
  io::prepare_output_dir(out, "--out", true, {dirs.begin(), dirs.end()});

  json summary{{"runs", dirs}};
  io::Report rep;
  rep.title = "Comparison of " + std::to_string(runs.size()) + " runs";
  rep.subtitle = "lathectl compare";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const json& s = runs[i].summary;
    rep.description += "Run " + std::to_string(i + 1) + ": " + runs[i].label +
                       (s.contains("scenario") && s["scenario"].is_string()
                            ? " (" + s["scenario"].get<std::string>() + ")"
                            : std::string()) +
                       "\n\n";
  }
  json settings, metrics, claims;
  std::size_t changed = 0;
  rep.tables.push_back(claims_table(runs, claims, changed));
  rep.tables.push_back(side_by_side("Settings that differ", runs, "settings", true, settings));
  rep.tables.push_back(side_by_side("Metrics", runs, "metrics", false, metrics));
  rep.plots = channel_plots(runs);
  rep.verdict = std::to_string(changed) + " claim(s) changed verdict, " +
                std::to_string(settings.size()) + " setting(s) differ";
  rep.verdict_ok = changed == 0;
  summary["settings_changed"] = settings;
  summary["metrics"] = metrics;
  summary["claims"] = claims;
  summary["claims_changed"] = changed;
  io::write_output_set(out, {{"summary.json", summary.dump(2) + "\n"},
                             {"report.html", io::render_html(rep)}});
  std::cout << "compare: " << runs.size() << " runs, " << settings.size()
            << " setting(s) differ, " << changed << " claim(s) changed verdict → "
            << (fs::path(out) / "report.html").string() << "\n";
  return 0;
}

}  // namespace

void add_compare(CLI::App& app, Commands& out) {
  struct Args {
    std::vector<std::string> dirs;
    std::string out = "compare-out";
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "compare",
      "Compare two or more runs' output directories: channels overlaid, settings and metrics "
      "side by side with differences, claims whose verdict changed");
  sub->add_option("runs", a->dirs, "output directories of `lathectl run` (or of the demo)")
      ->required()
      ->expected(2, -1);
  sub->add_option("--out", a->out, "output directory")->capture_default_str();
  out.push_back({sub, [a] { return compare(a->dirs, a->out); }});
}

}  // namespace lathectl::cli
