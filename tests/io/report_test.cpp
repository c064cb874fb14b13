#include "lathectl/io/report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace lathectl::io {
namespace {

std::size_t count_of(const std::string& haystack, const std::string& needle) {
  std::size_t n = 0;
  for (auto pos = haystack.find(needle); pos != std::string::npos;
       pos = haystack.find(needle, pos + needle.size())) {
    ++n;
  }
  return n;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The `points` attribute of every <polyline>, parsed into (x, y) pixel pairs.
std::vector<std::vector<std::pair<double, double>>> polylines(const std::string& html) {
  std::vector<std::vector<std::pair<double, double>>> out;
  const std::string key = "<polyline points=\"";
  for (auto pos = html.find(key); pos != std::string::npos; pos = html.find(key, pos + 1)) {
    const auto begin = pos + key.size();
    const auto end = html.find('"', begin);
    std::istringstream in(html.substr(begin, end - begin));
    std::vector<std::pair<double, double>> pts;
    std::string pair;
    while (in >> pair) {
      const auto comma = pair.find(',');
      pts.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
    }
    out.push_back(std::move(pts));
  }
  return out;
}

// The text of every <text> element (tick labels among them).
std::vector<std::string> svg_texts(const std::string& html) {
  std::vector<std::string> out;
  for (auto pos = html.find("<text"); pos != std::string::npos; pos = html.find("<text", pos + 1)) {
    const auto begin = html.find('>', pos) + 1;
    out.push_back(html.substr(begin, html.find("</text>", begin) - begin));
  }
  return out;
}

Series line_series(std::string name, std::size_t n, double dt) {
  Series s;
  s.name = std::move(name);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt;
    s.x.push_back(t);
    s.y.push_back(std::sin(t));
  }
  return s;
}

Report report_with_plot(Plot plot) {
  Report r;
  r.title = "t";
  r.plots.push_back(std::move(plot));
  return r;
}

TEST(Report, IsOneHtmlDocumentWithSectionsInOrder) {
  Report r;
  r.title = "Rig A step";
  r.subtitle = "examples/scenarios/rig_a.toml";
  r.description = "First paragraph,\nstill first.\n\n  \nSecond paragraph.";
  r.metrics = {{"overshoot", "4.2 %"}, {"settling time", "0.18 s"}};
  r.notes = {"note one", "note two"};
  r.tables.push_back({"Events", {"t [s]", "event"}, {{"1.5", "step"}, {"2.0", "alarm"}}});
  Plot p;
  p.title = "Speed";
  p.x_label = "time [s]";
  p.y_label = "speed [mm/min]";
  p.series.push_back(line_series("speed", 100, 0.1));
  r.plots.push_back(p);

  const std::string html = render_html(r);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0U);
  EXPECT_NE(html.find("<style>"), std::string::npos);
  EXPECT_NE(html.find("</html>"), std::string::npos);
  EXPECT_EQ(count_of(html, "<svg"), 1U);
  EXPECT_EQ(count_of(html, "<p>"), 2U);  // two description paragraphs
  EXPECT_NE(html.find("<li>note two</li>"), std::string::npos);
  EXPECT_NE(html.find("<td>overshoot</td><td>4.2 %</td>"), std::string::npos);

  const auto h1 = html.find("<h1>Rig A step</h1>");
  const auto sub = html.find("examples/scenarios/rig_a.toml");
  const auto para = html.find("Second paragraph.");
  const auto metrics = html.find("overshoot");
  const auto notes = html.find("note one");
  const auto table = html.find("alarm");
  const auto plot = html.find("<svg");
  ASSERT_NE(h1, std::string::npos);
  EXPECT_LT(h1, sub);
  EXPECT_LT(sub, para);
  EXPECT_LT(para, metrics);
  EXPECT_LT(metrics, notes);
  EXPECT_LT(notes, table);
  EXPECT_LT(table, plot);
  for (const char* label : {"Speed", "time [s]", "speed [mm/min]"}) {
    const auto texts = svg_texts(html);
    EXPECT_NE(std::find(texts.begin(), texts.end(), label), texts.end()) << label;
  }
}

TEST(Report, EscapesAllText) {
  Report r;
  r.title = "<script>alert('x')</script> & \"co\"";
  r.subtitle = "<b>sub</b>";
  r.description = "a < b & c > d";
  r.metrics = {{"<m>", "<v>"}};
  r.notes = {"<note>"};
  r.tables.push_back({"<table>", {"<h>"}, {{"<cell>"}}});
  Plot p;
  p.title = "<plot>";
  p.x_label = "<x>";
  p.y_label = "<y>";
  Series s = line_series("<series>", 10, 1.0);
  s.color = "red\" onload=\"x";
  p.series.push_back(s);
  p.markers.push_back({3.0, "<marker>"});
  r.plots.push_back(p);

  const std::string html = render_html(r);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; &quot;co&quot;"),
            std::string::npos);
  for (const char* tag : {"<b>", "<m>", "<v>", "<note>", "<table>", "<h>", "<cell>", "<plot>",
                          "<x>", "<y>", "<series>", "<marker>"}) {
    EXPECT_EQ(html.find(tag), std::string::npos) << tag;
  }
  EXPECT_NE(html.find("a &lt; b &amp; c &gt; d"), std::string::npos);
  EXPECT_NE(html.find("&lt;marker&gt;"), std::string::npos);
  EXPECT_EQ(html.find("onload=\""), std::string::npos);
}

TEST(Report, NoNetworkReferencesAndNoScripts) {
  Plot p;
  p.title = "plot";
  p.series.push_back(line_series("a", 500, 0.01));
  Series dashed = line_series("setpoint", 500, 0.01);
  dashed.dashed = true;
  p.series.push_back(dashed);
  p.markers.push_back({1.0, "event"});
  const std::string html = render_html(report_with_plot(p));
  const std::string lowered = lower(html);
  EXPECT_EQ(lowered.find("http"), std::string::npos);
  EXPECT_EQ(lowered.find("<script"), std::string::npos);
  EXPECT_EQ(lowered.find("<link"), std::string::npos);
  EXPECT_EQ(lowered.find("@import"), std::string::npos);
  EXPECT_EQ(lowered.find("src="), std::string::npos);
}

TEST(Report, NonFiniteValuesBreakTheLineAndNeverReachTheOutput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Series s = line_series("with gaps", 200, 0.05);
  s.y[50] = nan;
  s.y[120] = inf;
  s.x[160] = -inf;
  Plot p;
  p.title = "gaps";
  p.series.push_back(s);
  Series all_nan;
  all_nan.name = "all nan";  // the name is the only place "nan" may appear
  all_nan.x = {0.0, 1.0, 2.0};
  all_nan.y = {nan, nan, nan};
  p.series.push_back(all_nan);

  const std::string html = render_html(report_with_plot(p));
  EXPECT_EQ(count_of(html, "nan"), 1U);
  EXPECT_EQ(count_of(lower(html), "nan"), 1U);
  EXPECT_EQ(lower(html).find("inf"), std::string::npos);
  const auto lines = polylines(html);
  ASSERT_EQ(lines.size(), 4U);  // three gaps → four pieces
  std::size_t total = 0;
  for (const auto& l : lines) {
    total += l.size();
    for (const auto& [x, y] : l) {
      EXPECT_TRUE(std::isfinite(x));
      EXPECT_TRUE(std::isfinite(y));
    }
  }
  EXPECT_EQ(total, 197U);
}

TEST(Report, DecimationBoundsPointCountAndKeepsSpikes) {
  constexpr std::size_t kN = 100000;
  constexpr std::size_t kMaxPoints = 2000;
  Series s = line_series("noisy", kN, 1e-3);
  s.y[54321] = 1000.0;   // a single tall spike
  s.y[77777] = -1000.0;  // and a single deep dip
  Plot p;
  p.title = "spike";
  p.series.push_back(s);

  const std::string decimated = render_html(report_with_plot(p), kMaxPoints);
  const std::string full = render_html(report_with_plot(p), kN);
  const auto lines = polylines(decimated);
  const auto full_lines = polylines(full);
  ASSERT_EQ(lines.size(), 1U);
  ASSERT_EQ(full_lines.size(), 1U);
  EXPECT_LE(lines[0].size(), kMaxPoints + 4);
  EXPECT_GE(lines[0].size(), kMaxPoints / 2);
  EXPECT_EQ(full_lines[0].size(), kN);

  // Same axes with and without decimation, so the extreme pixels must coincide: the spike and
  // the dip survived.
  const auto y_extent = [](const std::vector<std::pair<double, double>>& pts) {
    const auto [lo, hi] = std::minmax_element(
        pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    return std::make_pair(lo->second, hi->second);
  };
  EXPECT_EQ(y_extent(lines[0]), y_extent(full_lines[0]));
  // x stays in order.
  EXPECT_TRUE(std::is_sorted(lines[0].begin(), lines[0].end(),
                             [](const auto& a, const auto& b) { return a.first < b.first; }));

  // The spike sets the y-axis range: its tick labels reach the hundreds.
  const auto texts = svg_texts(decimated);
  EXPECT_NE(std::find(texts.begin(), texts.end(), "1000"), texts.end());
  EXPECT_NE(std::find(texts.begin(), texts.end(), "-1000"), texts.end());
}

TEST(Report, TickLabelsAreNiceAndCompact) {
  Series s;
  s.name = "ramp";
  s.x = {0.0, 10.0};
  s.y = {0.0, 1.0};
  Plot p;
  p.series.push_back(s);
  const auto texts = svg_texts(render_html(report_with_plot(p)));
  for (const char* label : {"0", "2", "4", "6", "8", "10", "0.2", "0.4", "0.6", "0.8", "1.0"}) {
    EXPECT_NE(std::find(texts.begin(), texts.end(), label), texts.end()) << label;
  }
  for (const auto& t : texts) EXPECT_LE(t.size(), 8U) << t;

  Series big;
  big.x = {0.0, 1.0};
  big.y = {0.0, 3e9};
  Plot q;
  q.series.push_back(big);
  const auto big_texts = svg_texts(render_html(report_with_plot(q)));
  EXPECT_NE(std::find(big_texts.begin(), big_texts.end(), "1e9"), big_texts.end());
}

TEST(Report, EmptyPlotsAndSeriesRenderNoData) {
  Plot empty;
  empty.title = "empty";
  std::string html = render_html(report_with_plot(empty));
  EXPECT_NE(html.find(">no data<"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_EQ(html.find("<polyline"), std::string::npos);

  Plot empty_series;
  empty_series.series.push_back(Series{"nothing", {}, {}, "", false, false});
  empty_series.markers.push_back({2.0, "event"});
  html = render_html(report_with_plot(empty_series));
  EXPECT_NE(html.find(">no data<"), std::string::npos);
  EXPECT_EQ(lower(html).find("nan"), std::string::npos);

  Series mismatched{"mismatched", {1.0, 2.0, 3.0}, {}, "", false, false};
  Plot p;
  p.series.push_back(mismatched);
  EXPECT_NE(render_html(report_with_plot(p)).find(">no data<"), std::string::npos);
}

TEST(Report, ConstantAndSinglePointSeriesGetAUsableRange) {
  Series constant{"constant", {0.0, 1.0, 2.0}, {5.0, 5.0, 5.0}, "", false, false};
  Plot p;
  p.series.push_back(constant);
  std::string html = render_html(report_with_plot(p));
  EXPECT_EQ(html.find("no data"), std::string::npos);
  ASSERT_EQ(polylines(html).size(), 1U);
  const auto line = polylines(html)[0];
  EXPECT_EQ(line.front().second, line.back().second);
  auto texts = svg_texts(html);
  EXPECT_NE(std::find(texts.begin(), texts.end(), "5.0"), texts.end());
  EXPECT_EQ(lower(html).find("nan"), std::string::npos);

  Series single{"single", {3.0}, {0.0}, "", false, false};
  Plot q;
  q.series.push_back(single);
  html = render_html(report_with_plot(q));
  EXPECT_EQ(html.find("no data"), std::string::npos);
  EXPECT_NE(html.find("<circle"), std::string::npos);  // a lone point is still shown
  EXPECT_EQ(lower(html).find("nan"), std::string::npos);
}

TEST(Report, SeriesStylesLegendAndMarkers) {
  Series measured = line_series("measured", 50, 0.1);
  measured.points = true;
  Series setpoint = line_series("setpoint", 50, 0.1);
  setpoint.dashed = true;
  setpoint.color = "#123456";
  Series plain = line_series("plain", 50, 0.1);
  Plot p;
  p.series = {measured, setpoint, plain};
  p.markers = {{1.0, "alarm"}, {100.0, "outside the axis"}};
  const std::string html = render_html(report_with_plot(p));

  EXPECT_GE(count_of(html, "<circle"), 50U);
  EXPECT_EQ(count_of(html, "<polyline"), 2U);
  EXPECT_NE(html.find("stroke=\"#123456\" stroke-width=\"1.7\" stroke-linejoin=\"round\" "
                      "stroke-linecap=\"round\" stroke-dasharray="),
            std::string::npos);
  const auto texts = svg_texts(html);
  for (const char* name : {"measured", "setpoint", "plain", "alarm"}) {
    EXPECT_NE(std::find(texts.begin(), texts.end(), name), texts.end()) << name;
  }
  EXPECT_EQ(html.find("outside the axis"), std::string::npos);
  // Palette colours differ for the two series without a colour.
  const auto first = html.find("fill=\"#");
  const auto last = html.rfind("<polyline");
  ASSERT_NE(first, std::string::npos);
  const std::string first_colour = html.substr(first + 6, 7);
  const std::string last_colour = html.substr(html.find("stroke=\"#", last) + 8, 7);
  EXPECT_NE(first_colour, last_colour);
}

TEST(Report, IndexLinksToEveryReport) {
  const std::string html = render_index_html(
      "All <runs>",
      {{"Rig A step", "rig_a/report.html", "overshoot 4.2 % · settling 0.18 s", 0, "", {}},
       {"Rig B & C", "rig b/report.html?x=1&y=2", "alarm at 6.5 s", 0, "", {}}});
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0U);
  EXPECT_NE(html.find("<h1>All &lt;runs&gt;</h1>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"rig_a/report.html\">Rig A step</a>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"rig b/report.html?x=1&amp;y=2\">Rig B &amp; C</a>"),
            std::string::npos);
  EXPECT_NE(html.find("overshoot 4.2 % · settling 0.18 s"), std::string::npos);
  EXPECT_NE(html.find("alarm at 6.5 s"), std::string::npos);
  EXPECT_EQ(count_of(html, "<a href="), 2U);
  EXPECT_EQ(lower(html).find("http"), std::string::npos);

  const std::string empty = render_index_html("none", {});
  EXPECT_EQ(empty.find("<a href="), std::string::npos);
  EXPECT_NE(empty.find("</html>"), std::string::npos);
}

}  // namespace
}  // namespace lathectl::io
