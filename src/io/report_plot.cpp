// The report's SVG plots: axes, lines, points, timeline bands, markers and legends (their ticks
// and numbers in report_scale.cpp, decimation in report_layout.cpp).
#include "report_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lathectl::io::detail {

std::string escape(std::string_view s) {
  std::string out;
  out.reserve(s.size() + s.size() / 8);
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

namespace {

// Eight colours that stay distinguishable on white and for the common colour-vision deficiencies
// as far as eight can.
constexpr std::string_view kPalette[] = {"#2563eb", "#dc2626", "#16a34a", "#ea580c",
                                         "#7c3aed", "#0891b2", "#a16207", "#db2777"};
constexpr std::size_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

// Values beyond this are clamped before scaling so that ranges and pixel maths stay finite.
constexpr double kHuge = 1e300;

// ---------------------------------------------------------------------------------------------
// SVG plot

constexpr double kWidth = 900.0;
constexpr double kTop = 44.0;  // plot area top (title above)
constexpr double kPlotHeight = 212.0;
constexpr double kRight = 24.0;
constexpr double kLegendRow = 20.0;
constexpr double kLaneHeight = 22.0;  // one lane of a timeline band
constexpr double kEdgePad = 6.0;      // px between the frame and points at the x range's ends

struct Frame {
  double left = 0.0;
  double top = kTop;
  double width = 0.0;
  double height = kPlotHeight;
  Range x;
  Range y;

  double bottom() const { return top + height; }
  double right() const { return left + width; }
  double px(double v) const {
    const double clamped = std::clamp(v, -kHuge, kHuge);
    return left + (clamped - x.lo) / (x.hi - x.lo) * width;
  }
  double py(double v) const {
    const double clamped = std::clamp(v, -kHuge, kHuge);
    return bottom() - (clamped - y.lo) / (y.hi - y.lo) * height;
  }
};

std::string color_of(const Series& s, std::size_t index) {
  if (!s.color.empty()) return escape(s.color);
  return std::string(kPalette[index % kPaletteSize]);
}

std::string line(double x1, double y1, double x2, double y2, std::string_view cls) {
  std::string out = "<line class=\"";
  out += cls;
  out += "\" x1=\"" + coord(x1) + "\" y1=\"" + coord(y1) + "\" x2=\"" + coord(x2) + "\" y2=\"" +
         coord(y2) + "\"/>";
  return out;
}

// Writes a <text> (every one carries its class, so its size is known: text_style) and records
// its estimated box.
struct TextWriter {
  std::vector<PlacedText>* placed = nullptr;

  std::string text(double x, double y, std::string_view anchor, std::string_view cls,
                   std::string_view content) const {
    record(text_box(x, y, anchor, false, content, text_style(cls)), cls, content);
    std::string out = "<text x=\"" + coord(x) + "\" y=\"" + coord(y) + "\"";
    if (!anchor.empty()) out += " text-anchor=\"" + std::string(anchor) + "\"";
    out += " class=\"" + std::string(cls) + "\">" + escape(content) + "</text>";
    return out;
  }
  // Rotated −90° about (x, y), reading upwards.
  std::string rotated(double x, double y, std::string_view anchor, std::string_view cls,
                      std::string_view content) const {
    record(text_box(x, y, anchor, true, content, text_style(cls)), cls, content);
    return "<text transform=\"translate(" + coord(x) + " " + coord(y) +
           ") rotate(-90)\" text-anchor=\"" + std::string(anchor) + "\" class=\"" +
           std::string(cls) + "\">" + escape(content) + "</text>";
  }
  void record(const Box& b, std::string_view cls, std::string_view content) const {
    if (placed) placed->push_back({b, std::string(cls), std::string(content)});
  }
};

struct LegendItem {
  double x = 0.0;
  double row = 0.0;
  std::size_t series = 0;
};

// What a plot draws, before any pixel: its series (log10(y) on a log axis, non-positive values
// becoming gaps), their decimated runs of finite points, and the data extent (from all finite
// points, not only the kept ones, so the axes are the same with or without decimation; y only
// from the points inside a fixed x range).
struct PlotData {
  const Plot* plot = nullptr;
  bool timeline = false;  // lanes of coded bands, not lines
  bool fixed_x = false;   // the plot's own x range
  std::vector<Series> logged;
  std::vector<std::vector<Segment>> segments;
  bool has_data = false, has_points = false;
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;

  const std::vector<Series>& series() const { return logged.empty() ? plot->series : logged; }
};

void extend_extent(PlotData& d, const Series& s) {
  const Plot& plot = *d.plot;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite_point(s, i)) continue;
    if (d.fixed_x && (s.x[i] < plot.x_min || s.x[i] > plot.x_max)) continue;
    const double xv = std::clamp(s.x[i], -kHuge, kHuge);
    const double yv = std::clamp(s.y[i], -kHuge, kHuge);
    if (!d.has_data) {
      d.x_lo = d.x_hi = xv;
      d.y_lo = d.y_hi = yv;
      d.has_data = true;
    } else {
      d.x_lo = std::min(d.x_lo, xv);
      d.x_hi = std::max(d.x_hi, xv);
      d.y_lo = std::min(d.y_lo, yv);
      d.y_hi = std::max(d.y_hi, yv);
    }
  }
}

PlotData plot_data(const Plot& plot, std::size_t max_points) {
  PlotData d;
  d.plot = &plot;
  d.timeline = !plot.lanes.empty();
  d.fixed_x = std::isfinite(plot.x_min) && std::isfinite(plot.x_max) && plot.x_max > plot.x_min;
  if (plot.log_y && !d.timeline) {
    d.logged = plot.series;
    for (Series& s : d.logged)
      for (double& v : s.y) v = v > 0.0 ? std::log10(v) : std::nan("");
  }
  d.segments.reserve(d.series().size());
  for (const Series& s : d.series()) {
    extend_extent(d, s);
    d.segments.push_back(segments_of(s, max_points));
    d.has_points = d.has_points || s.points;
    for (const Segment& seg : d.segments.back()) d.has_points = d.has_points || seg.size() == 1;
  }
  if (!d.has_data) {
    // Empty axes; markers still give the time axis a meaningful extent when present.
    bool any_marker = false;
    for (const Marker& m : plot.markers) {
      if (!std::isfinite(m.x)) continue;
      const double xv = std::clamp(m.x, -kHuge, kHuge);
      d.x_lo = any_marker ? std::min(d.x_lo, xv) : xv;
      d.x_hi = any_marker ? std::max(d.x_hi, xv) : xv;
      any_marker = true;
    }
    if (!any_marker) d.x_hi = 1.0;
    d.y_lo = 0.0;
    d.y_hi = 1.0;
  }
  return d;
}

// The frame's ranges: x from the plot's fixed range or the data; y from lanes, the plot's fixed
// range, or the data widened (either end the plot fixes kept).
Frame plot_frame(const PlotData& d) {
  const Plot& plot = *d.plot;
  Frame f;
  f.x = d.fixed_x ? Range{plot.x_min, plot.x_max} : widen(d.x_lo, d.x_hi, 0.0);
  const auto fixed_y = [&](double v) { return plot.log_y ? (v > 0.0 ? std::log10(v) : NAN) : v; };
  const double fy_lo = fixed_y(plot.y_min), fy_hi = fixed_y(plot.y_max);
  if (d.timeline) {
    f.y = {0.0, static_cast<double>(plot.lanes.size())};
    f.height = kLaneHeight * static_cast<double>(plot.lanes.size());
  } else if (std::isfinite(fy_lo) && std::isfinite(fy_hi) && fy_hi > fy_lo) {
    f.y = {fy_lo, fy_hi};
  } else {
    f.y = d.has_data ? widen(d.y_lo, d.y_hi, 0.05) : Range{0.0, 1.0};
    if (std::isfinite(fy_lo) && fy_lo < f.y.hi) f.y.lo = fy_lo;
    if (std::isfinite(fy_hi) && fy_hi > f.y.lo) f.y.hi = fy_hi;
  }
  return f;
}

struct Axes {
  std::vector<double> y_ticks;
  std::vector<std::string> y_labels;
  Ticks xt;
  std::vector<std::string> x_labels;
};

// The ticks and their labels; the frame's left edge and width follow from the y labels' width.
Axes plot_axes(const PlotData& d, Frame& f) {
  const Plot& plot = *d.plot;
  Axes ax;
  // y ticks: lane names, decades, or 1-2-5 steps.
  if (d.timeline) {
    for (std::size_t i = 0; i < plot.lanes.size(); ++i) {
      ax.y_ticks.push_back(f.y.hi - static_cast<double>(i) - 0.5);
      ax.y_labels.push_back(plot.lanes[i].second);
    }
  } else {
    const Ticks yt = plot.log_y ? log_ticks(f.y.lo, f.y.hi) : make_ticks(f.y.lo, f.y.hi, 5.0);
    ax.y_ticks = yt.values;
    for (const double v : yt.values)
      ax.y_labels.push_back(plot.log_y ? log_tick_label(v)
                                       : tick_label(v, yt.step, f.y.lo, f.y.hi));
  }
  double longest = 0.0;
  for (const std::string& l : ax.y_labels)
    longest = std::max(longest, text_width(l, text_style("tick")));
  // Room for the tick labels (8 px from the axis) and the rotated axis label (to x ≈ 19).
  f.left = std::max(60.0, 32.0 + longest);
  f.width = kWidth - f.left - kRight;
  if (d.has_points && !d.fixed_x) {  // keep markers at the ends whole
    const double pad = (f.x.hi - f.x.lo) * kEdgePad / f.width;
    f.x = {f.x.lo - pad, f.x.hi + pad};
  }
  // x ticks: as many as fit without their labels touching.
  for (double target = 7.0; target >= 2.0; target -= 1.0) {
    ax.xt = make_ticks(f.x.lo, f.x.hi, target);
    ax.x_labels.clear();
    double widest = 0.0;
    for (const double v : ax.xt.values) {
      ax.x_labels.push_back(tick_label(v, ax.xt.step, f.x.lo, f.x.hi));
      widest = std::max(widest, text_width(ax.x_labels.back(), text_style("tick")));
    }
    const std::vector<double>& xv = ax.xt.values;
    const double spacing = xv.size() > 1 ? f.px(xv[1]) - f.px(xv[0]) : 1e9;
    if (widest + 10.0 < spacing) break;
  }
  return ax;
}

struct Legend {
  std::vector<LegendItem> items;
  double rows = 0.0;
};

// Legend layout: rows under the x-axis label, wrapped to the plot width.
Legend legend_layout(const Plot& plot, const Frame& f) {
  Legend lg;
  double lx = f.left;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const std::string& name = plot.series[i].name;
    if (name.empty()) continue;
    const double w = 28.0 + text_width(name, text_style("legend")) + 24.0;
    if (lg.items.empty()) {
      lg.rows = 1.0;
    } else if (lx + w > f.right() && lx > f.left) {
      lx = f.left;
      lg.rows += 1.0;
    }
    lg.items.push_back({lx, lg.rows - 1.0, i});
    lx += w;
  }
  return lg;
}

// The data's footprint in pixels, for placing marker labels off it.
void mark_data(Occupancy& occ, const PlotData& d, const Frame& f) {
  const std::vector<Series>& series = d.series();
  for (std::size_t si = 0; si < series.size(); ++si) {
    for (const Segment& seg : d.segments[si]) {
      for (std::size_t k = 0; k < seg.size(); ++k) {
        const double x = f.px(seg[k].first), y = f.py(seg[k].second);
        if (series[si].points || k == 0) {
          occ.mark_rect(x - 3.0, y - 3.0, x + 3.0, y + 3.0);
        } else {
          occ.mark_line(f.px(seg[k - 1].first), f.py(seg[k - 1].second), x, y);
        }
      }
    }
  }
}

// A timeline's bands, one lane per code (runs closer than half a pixel merged), marked in occ.
std::string timeline_bands(const PlotData& d, const Frame& f, const Axes& ax, Occupancy& occ) {
  const Plot& plot = *d.plot;
  std::string bands;
  for (std::size_t li = 0; li < plot.lanes.size(); ++li) {
    const double yc = f.py(ax.y_ticks[li]);
    std::vector<std::pair<double, double>> px_runs;  // merged where closer than half a pixel
    for (const Series& s : d.series()) {
      for (const auto& [a, b] : runs_of(s, plot.lanes[li].first)) {
        const double x0 = std::max(f.px(a), f.left);
        const double x1 = std::max(std::min(f.px(b), f.right()), x0 + 1.0);  // one sample shows
        if (x0 > f.right()) continue;
        if (!px_runs.empty() && x0 <= px_runs.back().second + 0.5) {
          px_runs.back().second = std::max(px_runs.back().second, x1);
        } else {
          px_runs.emplace_back(x0, x1);
        }
      }
    }
    bands += "<g fill=\"" + std::string(kPalette[li % kPaletteSize]) + "\">";
    for (const auto& [x0, x1] : px_runs) {
      occ.mark_rect(x0, yc - 7.0, x1, yc + 7.0);
      bands += "<rect x=\"" + coord(x0) + "\" y=\"" + coord(yc - 7.0) + "\" width=\"" +
               coord(x1 - x0) + "\" height=\"14\"/>";
    }
    bands += "</g>";
  }
  return bands;
}

struct MarkerLayout {
  std::string lines;
  std::vector<PlacedMarkerLabel> labels;
  std::vector<std::string> unplaced;
};

// Marker lines, in the plot area, and their labels beside them.
MarkerLayout marker_layout(const Plot& plot, const Frame& f, Occupancy& occ) {
  MarkerLayout mk;
  std::vector<MarkerLabel> wanted;
  for (const Marker& m : plot.markers) {
    if (!std::isfinite(m.x) || m.x < f.x.lo || m.x > f.x.hi) continue;
    const double x = f.px(m.x);
    mk.lines += line(x, f.top, x, f.bottom(), "m");
    occ.mark_line(x, f.top, x, f.bottom());
    wanted.push_back({x, m.label});
  }
  // The title is laid out first: marker labels may go in the strip between it and the frame.
  const Box title_box =
      text_box(f.left + f.width / 2.0, 24.0, "middle", false, plot.title, text_style("title"));
  std::vector<Box> taken{title_box};
  const Box frame_box{f.left, f.top, f.right(), f.bottom()};
  const Box above{4.0, title_box.y1 + 1.0, kWidth - 4.0, f.top};
  mk.labels = place_marker_labels(wanted, frame_box, above, occ, taken, mk.unplaced);
  return mk;
}

// The <svg> and its frame: title, grid, ticks and their labels, axes and axis labels.
void write_frame(std::string& out, const TextWriter& tw, const Plot& plot, const Frame& f,
                 const Axes& ax, const std::string& id, double height) {
  out += "<figure class=\"plot\">\n<svg class=\"chart\" viewBox=\"0 0 " + coord(kWidth) + " " +
         coord(height) + "\" role=\"img\" aria-label=\"" + escape(plot.title) + "\">\n";
  out += "<defs><clipPath id=\"" + id + "\"><rect x=\"" + coord(f.left - 4.0) + "\" y=\"" +
         coord(f.top - 4.0) + "\" width=\"" + coord(f.width + 8.0) + "\" height=\"" +
         coord(f.height + 8.0) + "\"/></clipPath></defs>\n";
  out += tw.text(f.left + f.width / 2.0, 24.0, "middle", "title", plot.title) + "\n";
  out += "<rect class=\"frame\" x=\"" + coord(f.left) + "\" y=\"" + coord(f.top) + "\" width=\"" +
         coord(f.width) + "\" height=\"" + coord(f.height) + "\"/>\n";

  // Grid and tick labels.
  out += "<g class=\"grid\">";
  for (const double v : ax.xt.values) {
    const double x = f.px(v);
    out += line(x, f.top, x, f.bottom(), "g");
  }
  for (const double v : ax.y_ticks) {
    const double y = f.py(v);
    out += line(f.left, y, f.right(), y, "g");
  }
  out += "</g>\n<g class=\"ticks\">";
  for (std::size_t i = 0; i < ax.xt.values.size(); ++i) {
    const double x = f.px(ax.xt.values[i]);
    out += line(x, f.bottom(), x, f.bottom() + 5.0, "t");
    out += tw.text(x, f.bottom() + 19.0, "middle", "tick", ax.x_labels[i]);
  }
  for (std::size_t i = 0; i < ax.y_ticks.size(); ++i) {
    const double y = f.py(ax.y_ticks[i]);
    out += line(f.left - 5.0, y, f.left, y, "t");
    out += tw.text(f.left - 8.0, y + 4.0, "end", "tick", ax.y_labels[i]);
  }
  out += "</g>\n";
  out += line(f.left, f.top, f.left, f.bottom(), "axis") +
         line(f.left, f.bottom(), f.right(), f.bottom(), "axis") + "\n";

  // Axis labels.
  if (!plot.x_label.empty())
    out +=
        tw.text(f.left + f.width / 2.0, f.bottom() + 40.0, "middle", "label", plot.x_label) + "\n";
  if (!plot.y_label.empty()) {
    const std::string y_label = plot.log_y ? plot.y_label + " (log scale)" : plot.y_label;
    out += tw.rotated(16.0, f.top + f.height / 2.0, "middle", "label", y_label) + "\n";
  }
}

void write_points(std::string& out, const std::vector<Segment>& segments, const std::string& color,
                  const Frame& f) {
  out += "<g class=\"points\" fill=\"" + color + "\">";
  for (const Segment& seg : segments) {
    for (const Point& p : seg) {
      const double x = f.px(p.first), y = f.py(p.second);
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      out += "<circle cx=\"" + coord(x) + "\" cy=\"" + coord(y) + "\" r=\"2.6\"/>";
    }
  }
  out += "</g>\n";
}

void write_lines(std::string& out, const Series& s, const std::vector<Segment>& segments,
                 const std::string& color, const Frame& f) {
  for (const Segment& seg : segments) {
    std::string pts;
    std::size_t count = 0;
    double last_x = 0.0, last_y = 0.0;
    for (const Point& p : seg) {
      const double x = f.px(p.first), y = f.py(p.second);
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      if (count > 0) pts += ' ';
      pts += coord(x) + "," + coord(y);
      last_x = x;
      last_y = y;
      ++count;
    }
    if (count == 1) {  // an isolated point between gaps: still show it
      out += "<circle cx=\"" + coord(last_x) + "\" cy=\"" + coord(last_y) +
             "\" r=\"1.8\" fill=\"" + color + "\"/>\n";
    } else if (count > 1) {
      out += "<polyline points=\"" + pts + "\" fill=\"none\" stroke=\"" + color +
             "\" stroke-width=\"1.7\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
      if (s.dashed) out += " stroke-dasharray=\"7 4\"";
      out += "/>\n";
    }
  }
}

// Legend (and, under it, the marker labels that found no room beside their lines).
void write_legend(std::string& out, const TextWriter& tw, const Plot& plot, const Legend& lg,
                  const std::vector<std::string>& unplaced, double left, double legend_top) {
  if (!lg.items.empty()) {
    out += "<g class=\"legend\">";
    for (const LegendItem& item : lg.items) {
      const Series& s = plot.series[item.series];
      const std::string color = color_of(s, item.series);
      const double y = legend_top + item.row * kLegendRow;
      if (s.points) {
        out += "<circle cx=\"" + coord(item.x + 11.0) + "\" cy=\"" + coord(y - 4.0) +
               "\" r=\"3.2\" fill=\"" + color + "\"/>";
      } else {
        out += "<line x1=\"" + coord(item.x) + "\" y1=\"" + coord(y - 4.0) + "\" x2=\"" +
               coord(item.x + 22.0) + "\" y2=\"" + coord(y - 4.0) + "\" stroke=\"" + color +
               "\" stroke-width=\"2.4\"";
        if (s.dashed) out += " stroke-dasharray=\"5 3\"";
        out += "/>";
      }
      out += tw.text(item.x + 28.0, y, "", "legend", s.name);
    }
    out += "</g>\n";
  }
  if (!unplaced.empty()) {
    std::string caption = "also marked: ";
    for (std::size_t i = 0; i < unplaced.size(); ++i) caption += (i ? ", " : "") + unplaced[i];
    out += tw.text(left, legend_top + lg.rows * kLegendRow, "", "legend", caption) + "\n";
  }
}

}  // namespace

void render_plot(std::string& out, const Plot& plot, std::size_t plot_index, std::size_t max_points,
                 std::vector<PlacedText>* placed) {
  // Layout: the data, the frame and its axes, the legend, then the marker labels placed off the
  // data, the bands and the title.
  const PlotData d = plot_data(plot, max_points);
  Frame f = plot_frame(d);
  const Axes ax = plot_axes(d, f);
  const Legend legend = legend_layout(plot, f);
  Occupancy occ(f.left, f.top, f.width, f.height);
  if (!d.timeline) mark_data(occ, d, f);
  const std::string bands = d.timeline ? timeline_bands(d, f, ax, occ) : std::string();
  const MarkerLayout mk = marker_layout(plot, f, occ);
  const double legend_top = f.bottom() + 54.0;
  const double caption_rows = mk.unplaced.empty() ? 0.0 : 1.0;
  const double height = legend.rows + caption_rows > 0.0
                            ? legend_top + (legend.rows + caption_rows) * kLegendRow + 6.0
                            : f.bottom() + 50.0;

  // Drawing, in that order: what comes later is on top.
  const TextWriter tw{placed};
  const std::string id = "clip" + std::to_string(plot_index);
  write_frame(out, tw, plot, f, ax, id, height);
  // Markers: dashed vertical lines under the data; their labels (with a white halo) on top.
  out += "<g class=\"marker\">" + mk.lines + "</g>\n";
  // Series: timeline bands, or lines and points (each series drawn in its order, the last on
  // top).
  out += "<g clip-path=\"url(#" + id + ")\">\n" + bands;
  const std::vector<Series>& series = d.series();
  for (std::size_t si = 0; si < series.size() && !d.timeline; ++si) {
    const std::string color = color_of(series[si], si);
    if (series[si].points)
      write_points(out, d.segments[si], color, f);
    else
      write_lines(out, series[si], d.segments[si], color, f);
  }
  out += "</g>\n";
  if (!mk.labels.empty()) {
    out += "<g class=\"marker\">";
    for (const PlacedMarkerLabel& l : mk.labels)
      out += l.rotated ? tw.rotated(l.x, l.y, l.anchor, "mark", l.text)
                       : tw.text(l.x, l.y, l.anchor, "mark", l.text);
    out += "</g>\n";
  }
  if (!d.has_data) {
    out += tw.text(f.left + f.width / 2.0, f.top + f.height / 2.0 + 6.0, "middle", "nodata",
                   "no data") +
           "\n";
  }
  write_legend(out, tw, plot, legend, mk.unplaced, f.left, legend_top);
  out += "</svg>\n</figure>\n";
}

std::string series_color(const Series& s, std::size_t index) { return color_of(s, index); }

}  // namespace lathectl::io::detail
