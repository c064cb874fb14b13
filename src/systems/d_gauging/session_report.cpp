// `lathectl report DIR` of system D's series on LinuxCNC (scripts/linuxcnc-sim-gauge --out DIR):
// the registry's session report for system D (entry.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/format.hpp"
#include "lathectl/io/json_file.hpp"
#include "lathectl/io/operation_log.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "systems/d_gauging/entry.hpp"

namespace lathectl::systems::d_gauging {
namespace {

namespace fs = std::filesystem;
using io::fixed;

// System D's series on LinuxCNC (scripts/linuxcnc-sim-gauge's summary.json): every number read
// is checked (JsonFile names the file, line and key of a bad one).
// The histogram: bins of a tenth of the tolerance over ±1.5 tolerances (the limits inside),
// wider when a size lies beyond, at most kMaxHistogramBins of them (a part far off widens the
// bins instead of multiplying them); the normal law of the series' own mean and σ.
constexpr double kMaxHistogramBins = 400.0;
constexpr double kMaxSizeErrorUm = 1e12;

io::Plot size_histogram(const std::vector<double>& sizes, double tol, double mean, double sigma) {
  double lo = -1.5 * tol, hi = 1.5 * tol;
  for (double e : sizes) {
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  const double w = std::max(0.1 * tol, (hi - lo) / (kMaxHistogramBins - 1.0));
  const double n = std::min(std::ceil((hi - lo) / w), kMaxHistogramBins - 1.0);  // finite: < 400
  const auto bins = static_cast<std::size_t>(n) + 1;
  std::vector<double> counts(bins, 0.0);
  for (double e : sizes) counts[static_cast<std::size_t>(std::clamp((e - lo) / w, 0.0, n))] += 1.0;
  io::Series hist{"finished sizes (" + std::to_string(sizes.size()) + " parts)",
                  {},
                  {},
                  "#1f77b4",
                  false,
                  false};
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
                         (sigma * std::sqrt(2.0 * std::numbers::pi)) * std::exp(-0.5 * z * z));
    }
    h.series.push_back(normal);
  }
  return h;
}

int gauge_series_report(const fs::path& summary, const std::string& out_arg) {
  const fs::path out = out_arg.empty() ? summary.parent_path() / "report.html" : fs::path(out_arg);
  io::check_output_file(out, "--out", {summary});
  const io::JsonFile f = io::JsonFile::read(summary, "the series' summary");
  const auto& doc = f.doc();
  if (!doc.is_object() || !doc.contains("metrics") || !doc["metrics"].is_object())
    f.fail("metrics", "expected the series' metrics");
  const auto& m = doc["metrics"];
  const auto num = [&](const char* k) { return f.number(m, "metrics", k); };
  const double tol = num("tolerance_um"), mean = num("size_mean_error_um");
  // The histogram's bins are tenths of it; a size's limits are target ± it.
  if (!(tol > 0.0) || tol > 1e6)
    f.fail("metrics.tolerance_um", "expected a tolerance above 0 and at most 1e6 µm, got " +
                                       io::fmt(tol));
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
  io::Table t{"Finished sizes",
              {"part", "finished − target [µm]", "steps: size at each [µm]",
               "crossing to standstill [ms]", "ended by", "alarm"},
              {}};
  std::vector<double> sizes;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const auto& p = parts[i];
    const std::string key = io::JsonFile::element("parts_detail", i);
    if (!p.is_object()) f.fail(key, "expected a part");
    const double e = f.number(p, key, "error_um");
    if (std::abs(e) > kMaxSizeErrorUm)  // the histogram's range stays finite
      f.fail(io::JsonFile::member(key, "error_um"),
             "expected a size error of at most 1e12 µm, got " + io::fmt(e));
    sizes.push_back(e);
    std::string steps;
    if (p.contains("steps") && p["steps"].is_array())
      for (std::size_t j = 0; j < p["steps"].size(); ++j)
        steps +=
            (j ? ", " : "") +
            fixed(f.number(p["steps"][j], io::JsonFile::element(key + ".steps", j), "size_um"), 2);
    const bool backstop =
        p.contains("backstop") && p["backstop"].is_boolean() && p["backstop"].get<bool>();
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

}  // namespace

// scripts/linuxcnc-sim-gauge's directory (or its summary.json), no operation log.
bool is_session(const fs::path& path) {
  return io::is_runner_output(path, {"parts.csv"});
}

int session_report(const fs::path& path, const std::string& out) {
  return gauge_series_report((fs::is_directory(path) ? path : path.parent_path()) / "summary.json",
                             out);
}

}  // namespace lathectl::systems::d_gauging
