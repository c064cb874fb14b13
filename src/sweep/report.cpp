// report.html of a sweep: the metrics over the varied keys (lines for one grid key, a heat map for
// two, one per combination of the grid keys beyond two; random samples averaged per grid point),
// a scatter for a random key alone, and the failed cases.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "lathectl/io/report.hpp"
#include "sweep/engine.hpp"

namespace lathectl::sweep {
namespace {

constexpr std::size_t kMaxMetricsDrawn = 12;
constexpr std::size_t kMaxHeatMaps = 60;

std::string label(const Value& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  return to_text(v);
}

// metric value of each case (NaN: none), by case id.
using Column = std::vector<double>;

// The mean over the random samples of each grid point (cases samples·p … samples·p + samples−1).
std::vector<double> per_point(const Column& col, std::size_t samples) {
  std::vector<double> out;
  for (std::size_t p = 0; p * samples < col.size(); ++p) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t s = 0; s < samples; ++s)
      if (std::isfinite(col[p * samples + s])) sum += col[p * samples + s], ++n;
    out.push_back(n ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

void line_plots(const Spec& spec, const std::string& metric, const Column& col,
                io::Report& rep) {
  const auto& g = spec.grid[0];
  const auto y = per_point(col, std::max<std::size_t>(1, spec.samples));
  io::Plot p;
  p.title = metric + " over " + g.key;
  p.x_label = g.key;
  p.y_label = metric;
  io::Series s;
  s.name = metric + (spec.samples > 1 ? " (mean of the samples)" : "");
  bool numeric = true;
  for (const auto& v : g.values) numeric &= std::isfinite(number_of(v));
  for (std::size_t i = 0; i < g.values.size(); ++i) {  // strings, booleans: by their index
    s.x.push_back(numeric ? number_of(g.values[i]) : static_cast<double>(i));
    s.y.push_back(y[i]);
    if (!numeric) p.x_label += std::string(i ? ", " : " (") + std::to_string(i) + ": " +
                               label(g.values[i]) + (i + 1 == g.values.size() ? ")" : "");
  }
  s.points = g.values.size() < 3;
  p.series.push_back(std::move(s));
  rep.plots.push_back(std::move(p));
}

void heat_maps(const Spec& spec, const std::string& metric, const Column& col, io::Report& rep) {
  const auto z = per_point(col, std::max<std::size_t>(1, spec.samples));
  const auto& gx = spec.grid[1];  // the faster of the two: columns
  const auto& gy = spec.grid[0];
  const std::size_t cell = gx.values.size() * gy.values.size();
  std::size_t per_map = 1;  // grid points of one combination of the other keys
  for (std::size_t k = 2; k < spec.grid.size(); ++k) per_map *= spec.grid[k].values.size();
  for (std::size_t m = 0; m < per_map && rep.heat_maps.size() < kMaxHeatMaps; ++m) {
    io::HeatMap h{metric, gx.key, gy.key, metric, {}, {}, {}};
    for (const auto& v : gx.values) h.xs.push_back(label(v));
    for (const auto& v : gy.values) h.ys.push_back(label(v));
    h.z.assign(gy.values.size(), std::vector<double>(gx.values.size()));
    for (std::size_t c = 0; c < cell; ++c)  // point index: (iy·nx + ix)·per_map + m
      h.z[c / gx.values.size()][c % gx.values.size()] = z[c * per_map + m];
    std::size_t rest = m;
    std::string others;
    for (std::size_t k = spec.grid.size(); k-- > 2;) {
      const auto& g = spec.grid[k];
      others = g.key + " = " + label(g.values[rest % g.values.size()]) +
               (others.empty() ? "" : ", " + others);
      rest /= g.values.size();
    }
    if (!others.empty()) h.title += " at " + others;
    rep.heat_maps.push_back(std::move(h));
  }
}

void scatter(const Spec& spec, const std::vector<std::vector<Value>>& values,
             const std::string& metric, const Column& col, io::Report& rep) {
  const std::size_t k = spec.grid.size();  // the first random key
  io::Plot p;
  p.title = metric + " over " + spec.random[0].key;
  p.x_label = spec.random[0].key;
  p.y_label = metric;
  io::Series s;
  s.name = metric;
  s.points = true;
  for (std::size_t i = 0; i < values.size(); ++i) {
    s.x.push_back(number_of(values[i][k]));
    s.y.push_back(col[i]);
  }
  p.series.push_back(std::move(s));
  rep.plots.push_back(std::move(p));
}

io::Table failed_table(const Spec& spec, const std::vector<std::vector<Value>>& values,
                       const std::vector<Result>& results) {
  io::Table t{"Failed cases", {"case"}, {}};
  for (const auto& k : spec.varied_keys()) t.header.push_back(k);
  t.header.push_back("message");
  for (const auto& r : results) {
    if (r.status == "ok") continue;
    std::vector<std::string> row{std::to_string(r.case_id)};
    for (const auto& v : values.at(static_cast<std::size_t>(r.case_id))) row.push_back(label(v));
    row.push_back(r.message);
    t.rows.push_back(std::move(row));
  }
  return t;
}

}  // namespace

std::string report_html(const Spec& spec, const std::vector<std::vector<Value>>& values,
                        const std::vector<Result>& results,
                        const std::vector<std::string>& metrics) {
  io::Report rep;
  rep.title = "Sweep " + spec.file;
  rep.subtitle = spec.scenario.string();
  rep.doc_page = "sweep.md";
  rep.plots_first = true;  // the map above the list of failed cases
  std::size_t ok = 0;
  double cpu = 0.0;
  std::vector<const Result*> by_case(values.size(), nullptr);
  for (const auto& r : results) {
    ok += r.status == "ok";
    cpu += r.elapsed_s;
    if (static_cast<std::size_t>(r.case_id) < values.size())
      by_case[static_cast<std::size_t>(r.case_id)] = &r;
  }
  rep.metrics = {{"cases", std::to_string(values.size())},
                 {"ok", std::to_string(ok)},
                 {"error", std::to_string(results.size() - ok)},
                 {"not run", std::to_string(values.size() - results.size())},
                 {"run time, sum of the cases [s]", to_text(std::round(cpu * 1000) / 1000)}};
  const std::size_t drawn = std::min(metrics.size(), kMaxMetricsDrawn);
  if (drawn < metrics.size())
    rep.notes.push_back("The plots show the first " + std::to_string(drawn) + " of " +
                        std::to_string(metrics.size()) +
                        " metrics; [output] metrics chooses them (results.csv has them all).");
  if (spec.samples > 1 && !spec.grid.empty())
    rep.notes.push_back("Each grid point is the mean of its " + std::to_string(spec.samples) +
                        " random samples' values (failed cases left out).");
  std::vector<Column> cols(drawn, Column(values.size(), std::numeric_limits<double>::quiet_NaN()));
  std::map<std::string, std::size_t> index;
  for (std::size_t m = 0; m < drawn; ++m) index.emplace(metrics[m], m);
  for (std::size_t i = 0; i < values.size(); ++i)  // each summary parsed once
    if (by_case[i] && by_case[i]->summary)
      for (const auto& [name, v] : metrics_of(*by_case[i]->summary))
        if (const auto it = index.find(name); it != index.end()) cols[it->second][i] = v;
  for (std::size_t m = 0; m < drawn; ++m) {
    if (std::none_of(cols[m].begin(), cols[m].end(), [](double v) { return std::isfinite(v); }))
      continue;  // in no case's summary (a warning says so)
    if (spec.grid.size() == 1)
      line_plots(spec, metrics[m], cols[m], rep);
    else if (spec.grid.size() >= 2)
      heat_maps(spec, metrics[m], cols[m], rep);
    else
      scatter(spec, values, metrics[m], cols[m], rep);
  }
  if (spec.lobes) {  // [report]: the lobes over the heat maps, the verdicts against them
    Column chatter(values.size(), std::numeric_limits<double>::quiet_NaN());
    if (!spec.lobes->chatter.empty())
      for (std::size_t i = 0; i < values.size(); ++i)
        if (by_case[i] && by_case[i]->summary)
          for (const auto& [name, v] : metrics_of(*by_case[i]->summary))
            if (name == spec.lobes->chatter) chatter[i] = v;
    for (auto& h : rep.heat_maps)
      if (h.z_label == spec.lobes->chatter) {  // blue: no chatter, red: chatter
        h.z_centre = spec.lobes->chatter_above;
        h.log_z = spec.lobes->chatter_above > 0.0 &&
                  std::all_of(chatter.begin(), chatter.end(), [](double v) { return !(v <= 0.0); });
      }
    lobes_overlay(spec, per_point(chatter, std::max<std::size_t>(1, spec.samples)), rep);
  }
  if (ok < results.size()) rep.tables.push_back(failed_table(spec, values, results));
  return io::render_html(rep);
}

}  // namespace lathectl::sweep
