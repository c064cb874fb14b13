// The reports' interactive plots: which plots get a chart, their data as min/max
// pyramids (sim/plot_pyramid.hpp) in one JSON block, and the inlined uPlot library and page script
// (report_plot_script.js), both embedded at build time (cmake/ReportAssets.cmake).
#include "report_interactive.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/io/base64.hpp"
#include "lathectl/sim/plot_pyramid.hpp"
#include "report_plot.hpp"

namespace lathectl::io::detail {

// report_assets.cpp, generated from node_modules/uplot and report_plot_script.js.
extern const unsigned char kUplotJs[];
extern const std::size_t kUplotJs_size;
extern const unsigned char kUplotCss[];
extern const std::size_t kUplotCss_size;
extern const unsigned char kUplotLicense[];
extern const std::size_t kUplotLicense_size;
extern const unsigned char kPlotScript[];
extern const std::size_t kPlotScript_size;

namespace {

std::string_view asset(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A series' recorded data, for sharing one pyramid between plots that show the same channel.
std::string data_key(const Series& s) {
  if (s.pyramid)  // a streamed record's: shared by pointer
    return "p" + std::to_string(reinterpret_cast<std::uintptr_t>(s.pyramid.get()));
  const std::size_t n = std::min(s.x.size(), s.y.size());
  std::string key(reinterpret_cast<const char*>(s.x.data()), n * sizeof(double));
  key.append(reinterpret_cast<const char*>(s.y.data()), n * sizeof(double));
  return std::to_string(std::hash<std::string>{}(key)) + ":" + std::to_string(n);
}

nlohmann::json pyramid_json(const Series& s, std::size_t max_values, bool& monotonic,
                            std::size_t& bytes) {
  using sim::PlotPyramid;
  std::shared_ptr<const PlotPyramid> built = s.pyramid;
  if (!built) {  // x/y are the whole record
    PlotPyramid::Options o;
    o.max_values_per_level = max_values;
    auto b = std::make_shared<PlotPyramid>(o);
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) b->push(s.x[i], s.y[i]);
    b->finish();
    built = std::move(b);
  }
  const PlotPyramid& p = *built;
  monotonic = p.monotonic();
  nlohmann::json levels = nlohmann::json::array();
  for (const auto& l : p.levels()) {
    // A level over the budget's cap is left out, as a pyramid built here would drop it (the
    // coarsest is kept whatever its size).
    if (l.y.size() > max_values && &l != &p.levels().back()) continue;
    nlohmann::json j{{"b", l.bucket}, {"y", base64_floats(l.y)}};
    bytes += j["y"].get_ref<const std::string&>().size();
    if (!l.x.empty()) {
      j["x"] = base64_floats(l.x);
      bytes += j["x"].get_ref<const std::string&>().size();
    }
    levels.push_back(std::move(j));
  }
  return {{"n", p.samples()},
          {"x0", p.x0()},
          {"x1", p.x_last()},
          {"dx", p.dx()},
          {"uniform", p.uniform()},
          {"levels", std::move(levels)}};
}

// The plots' data: {"blobs": [pyramid...], "plots": [{plot, title, series: [{blob,...}]...}]}.
// Each distinct series gets at most `max_values` values per level.
nlohmann::json plot_data(const std::vector<Plot>& plots, std::size_t max_values,
                         std::size_t& bytes) {
  nlohmann::json blobs = nlohmann::json::array();
  nlohmann::json out_plots = nlohmann::json::array();
  std::map<std::string, std::size_t> blob_of;
  std::vector<bool> blob_monotonic;
  for (std::size_t pi = 0; pi < plots.size(); ++pi) {
    const Plot& plot = plots[pi];
    if (!time_axis(plot)) continue;
    nlohmann::json series = nlohmann::json::array();
    bool ok = true;
    for (std::size_t si = 0; si < plot.series.size(); ++si) {
      const Series& s = plot.series[si];
      const std::string key = data_key(s);
      auto it = blob_of.find(key);
      if (it == blob_of.end()) {
        bool monotonic = true;
        blobs.push_back(pyramid_json(s, max_values, monotonic, bytes));
        blob_monotonic.push_back(monotonic);
        it = blob_of.emplace(key, blobs.size() - 1).first;
      }
      ok = ok && blob_monotonic[it->second];
      series.push_back({{"blob", it->second},
                        {"name", s.name},
                        {"color", series_color(s, si)},  // as in the SVG
                        {"dashed", s.dashed},
                        {"points", s.points}});
    }
    if (!ok || series.empty()) continue;  // x runs backwards: the SVG alone shows it
    nlohmann::json markers = nlohmann::json::array();
    for (const Marker& m : plot.markers)
      if (std::isfinite(m.x)) markers.push_back({{"x", m.x}, {"label", m.label}});
    out_plots.push_back({{"plot", pi},
                         {"title", plot.title},
                         {"x_label", plot.x_label},
                         {"y_label", plot.y_label},
                         {"series", std::move(series)},
                         {"markers", std::move(markers)}});
  }
  return {{"blobs", std::move(blobs)}, {"plots", std::move(out_plots)}};
}

// JSON inside <script>: "</" cannot end the element once written "<\/".
std::string script_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    out += json[i];
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') out += '\\';
  }
  return out;
}

}  // namespace

const std::string_view kInteractiveStyle = R"css(
.plot-bar { position: sticky; top: 0; z-index: 5; display: flex; flex-wrap: wrap; gap: 6px;
  align-items: center; background: #fff; padding: 6px 0 8px; border-bottom: 1px solid #e5e8eb;
  margin-bottom: 10px; font-size: 13px; }
.plot-bar button { font: inherit; padding: 2px 10px; border: 1px solid #d0d7de; border-radius: 6px;
  background: #f6f8fa; cursor: pointer; }
.plot-bar button:hover { background: #eaeef2; }
.plot-bar .readout { color: #24292f; font-variant-numeric: tabular-nums; margin-left: 6px; }
.plot-bar .hint { color: #8c959f; margin-left: auto; }
.uplot-host { margin: 0 0 18px; }
.uplot-host .u-title { font-size: 15px; font-weight: 600; }
.uplot-host .u-legend { font-size: 13px; text-align: left; }
.js-plots .plot-box.live > figure.plot { display: none; }
@media print {
  .plot-bar, .uplot-host { display: none; }
  .js-plots .plot-box.live > figure.plot { display: block; }
}
)css";

bool time_axis(const Plot& plot) {
  std::string l;
  for (const char c : plot.x_label.substr(0, 4))
    l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return l == "time";
}

bool has_interactive_plots(const std::vector<Plot>& plots) {
  return std::any_of(plots.begin(), plots.end(), [](const Plot& p) { return time_axis(p); });
}

void render_interactive(std::string& out, const std::vector<Plot>& plots,
                        std::size_t budget_bytes) {
  if (!has_interactive_plots(plots)) return;
  // The finest levels that fit the budget: from the recorded samples of every distinct series,
  // halve the per-level cap until the estimate fits (a level and the coarser ones hold about
  // 5/3 of its values, 4 bytes each, 4/3 for base64; uneven x doubles it), then build; build
  // again with half the cap should the estimate have been short.
  std::map<std::string, std::size_t> samples;
  for (const Plot& p : plots)
    if (time_axis(p))
      for (const Series& s : p.series) samples[data_key(s)] = std::min(s.x.size(), s.y.size());
  const auto estimate = [&](std::size_t cap) {
    double bytes = 0.0;
    for (const auto& kv : samples)
      bytes += static_cast<double>(std::min(kv.second, cap)) * (5.0 / 3.0) * 4.0 * (4.0 / 3.0);
    return bytes;
  };
  std::size_t max_values = std::size_t{1} << 20;
  while (max_values > 4096 && estimate(max_values) > static_cast<double>(budget_bytes))
    max_values /= 2;
  nlohmann::json data;
  for (;;) {
    std::size_t bytes = 0;
    data = plot_data(plots, max_values, bytes);
    if (bytes <= budget_bytes || max_values <= 4096) break;
    max_values /= 2;
  }
  if (data["plots"].empty()) return;
  out += "<style>";
  out += asset(kUplotCss, kUplotCss_size);
  out += "</style>\n<script type=\"application/json\" id=\"lathectl-plot-data\">";
  out += script_safe(data.dump());
  out += "</script>\n<script>/* uPlot ";
  std::string license(asset(kUplotLicense, kUplotLicense_size));
  for (std::size_t at = license.find("*/"); at != std::string::npos; at = license.find("*/"))
    license.replace(at, 2, "* /");
  out += license;
  out += "*/\n";
  out += asset(kUplotJs, kUplotJs_size);
  out += "\n</script>\n<script>";
  out += asset(kPlotScript, kPlotScript_size);
  out += "</script>\n";
}

}  // namespace lathectl::io::detail
