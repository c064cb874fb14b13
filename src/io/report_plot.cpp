// The report's SVG plots: ticks, decimation (min/max per pixel column), axes, legends.
#include "report_plot.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>
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

// Locale-independent (std::to_chars), unlike printf, so a program that calls setlocale() cannot
// turn the decimal point of an SVG coordinate into a comma.
std::string fixed(double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed, decimals);
  if (r.ec != std::errc{}) return "0";
  return std::string(buf, r.ptr);
}

// %g-like with a compact exponent: 1.5e+06 → 1.5e6, 2e-05 → 2e-5.
std::string general(double v, int precision) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, precision);
  if (r.ec != std::errc{}) return "0";
  std::string s(buf, r.ptr);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::string mantissa = s.substr(0, e);
  std::string exponent = s.substr(e + 1);
  bool negative = false;
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) {
    negative = exponent[0] == '-';
    exponent.erase(0, 1);
  }
  const auto nz = exponent.find_first_not_of('0');
  exponent = nz == std::string::npos ? "0" : exponent.substr(nz);
  return mantissa + (negative ? "e-" : "e") + exponent;
}

// One SVG coordinate, 0.1 px resolution, no trailing ".0", never "-0".
std::string coord(double v) {
  if (!std::isfinite(v)) return "0";  // unreachable by construction; never emit nan/inf
  std::string s = fixed(std::round(v * 10.0) / 10.0, 1);
  if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
  if (s == "-0") s = "0";
  return s;
}

// Tick label for v on an axis [lo, hi] with the given (1-2-5) step: plain decimals for ordinary
// magnitudes, just enough significant digits otherwise.
std::string tick_label(double v, double step, double lo, double hi) {
  if (std::abs(v) < step * 1e-6) return "0";
  const double mag = std::max(std::abs(lo), std::abs(hi));
  const double step_exp = std::floor(std::log10(step) + 1e-9);
  if (mag >= 1e-3 && mag < 1e6 && step >= 1e-6) {
    const int decimals = step_exp < 0.0 ? static_cast<int>(-step_exp) : 0;
    return fixed(v, decimals);
  }
  const double mag_exp = std::floor(std::log10(mag) + 1e-9);
  const int digits = std::clamp(static_cast<int>(mag_exp - step_exp) + 1, 1, 15);
  return general(v, digits);
}

// ---------------------------------------------------------------------------------------------
// Axis scaling

double nice_step(double raw) {
  if (!(raw > 0.0) || !std::isfinite(raw)) return 1.0;
  const double exp10 = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / exp10;
  const double n = f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0;  // nearest 1-2-5
  return n * exp10;
}

struct Ticks {
  std::vector<double> values;
  double step = 1.0;
};

Ticks make_ticks(double lo, double hi, double target_count) {
  Ticks t;
  t.step = nice_step((hi - lo) / target_count);
  const double start = std::ceil(lo / t.step - 1e-9) * t.step;
  for (int i = 0; i < 100; ++i) {
    double v = start + static_cast<double>(i) * t.step;
    if (v > hi + t.step * 1e-9) break;
    if (std::abs(v) < t.step * 1e-9) v = 0.0;
    t.values.push_back(v);
  }
  return t;
}

struct Range {
  double lo = 0.0;
  double hi = 1.0;
};

// Widens a degenerate (constant, or so narrow that pixel maths would underflow) range; pads a
// proper one by `pad_fraction` of its span on each side.
Range widen(double lo, double hi, double pad_fraction) {
  constexpr double kTiny = 1e-200;
  const double span = hi - lo;
  const double scale = std::max(std::abs(lo), std::abs(hi));
  if (span > scale * 1e-12 && span > kTiny) {
    return {lo - span * pad_fraction, hi + span * pad_fraction};
  }
  const double pad = scale > kTiny ? scale * 0.1 : 1.0;
  return {lo - pad, hi + pad};
}

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

// Decade ticks on a log10 axis [lo, hi] (in decades); 2 and 5 between them when the axis spans
// fewer than three decades.
Ticks log_ticks(double lo, double hi) {
  Ticks t;
  t.step = 1.0;
  const bool fine = hi - lo < 3.0;
  for (double d = std::floor(lo); d <= std::ceil(hi) && t.values.size() < 60; d += 1.0) {
    for (const double m : {1.0, 2.0, 5.0}) {
      if (m > 1.0 && !fine) continue;
      const double v = d + std::log10(m);
      if (v >= lo - 1e-9 && v <= hi + 1e-9) t.values.push_back(v);
    }
  }
  return t;
}

std::string log_tick_label(double decades) {
  const double v = std::pow(10.0, decades);
  if (v < 1e-4 || v >= 1e6) return general(v, 2);
  const double d = std::floor(decades + 1e-9);
  return fixed(v, d < 0.0 ? static_cast<int>(-d) : 0);
}

struct LegendItem {
  double x = 0.0;
  double row = 0.0;
  std::size_t series = 0;
};

}  // namespace

void render_plot(std::string& out, const Plot& plot, std::size_t plot_index, std::size_t max_points,
                 std::vector<PlacedText>* placed) {
  const bool timeline = !plot.lanes.empty();
  // A log axis plots log10(y) (non-positive values become gaps) on a linear frame.
  std::vector<Series> logged;
  if (plot.log_y && !timeline) {
    logged = plot.series;
    for (Series& s : logged)
      for (double& v : s.y) v = v > 0.0 ? std::log10(v) : std::nan("");
  }
  const std::vector<Series>& series = logged.empty() ? plot.series : logged;
  const bool fixed_x =
      std::isfinite(plot.x_min) && std::isfinite(plot.x_max) && plot.x_max > plot.x_min;

  // Decimated runs of finite points per series, and the data extent (from all finite points,
  // not only the kept ones, so the axes are the same with or without decimation; y only from
  // the points inside a fixed x range).
  std::vector<std::vector<Segment>> segments;
  segments.reserve(series.size());
  bool has_data = false, has_points = false;
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
  for (const Series& s : series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (!finite_point(s, i)) continue;
      if (fixed_x && (s.x[i] < plot.x_min || s.x[i] > plot.x_max)) continue;
      const double xv = std::clamp(s.x[i], -kHuge, kHuge);
      const double yv = std::clamp(s.y[i], -kHuge, kHuge);
      if (!has_data) {
        x_lo = x_hi = xv;
        y_lo = y_hi = yv;
        has_data = true;
      } else {
        x_lo = std::min(x_lo, xv);
        x_hi = std::max(x_hi, xv);
        y_lo = std::min(y_lo, yv);
        y_hi = std::max(y_hi, yv);
      }
    }
    segments.push_back(segments_of(s, max_points));
    has_points = has_points || s.points;
    for (const Segment& seg : segments.back()) has_points = has_points || seg.size() == 1;
  }
  if (!has_data) {
    // Empty axes; markers still give the time axis a meaningful extent when present.
    bool any_marker = false;
    for (const Marker& m : plot.markers) {
      if (!std::isfinite(m.x)) continue;
      const double xv = std::clamp(m.x, -kHuge, kHuge);
      x_lo = any_marker ? std::min(x_lo, xv) : xv;
      x_hi = any_marker ? std::max(x_hi, xv) : xv;
      any_marker = true;
    }
    if (!any_marker) x_hi = 1.0;
    y_lo = 0.0;
    y_hi = 1.0;
  }

  Frame f;
  f.x = fixed_x ? Range{plot.x_min, plot.x_max} : widen(x_lo, x_hi, 0.0);
  const auto fixed_y = [&](double v) { return plot.log_y ? (v > 0.0 ? std::log10(v) : NAN) : v; };
  const double fy_lo = fixed_y(plot.y_min), fy_hi = fixed_y(plot.y_max);
  if (timeline) {
    f.y = {0.0, static_cast<double>(plot.lanes.size())};
    f.height = kLaneHeight * static_cast<double>(plot.lanes.size());
  } else if (std::isfinite(fy_lo) && std::isfinite(fy_hi) && fy_hi > fy_lo) {
    f.y = {fy_lo, fy_hi};
  } else {
    f.y = has_data ? widen(y_lo, y_hi, 0.05) : Range{0.0, 1.0};
    if (std::isfinite(fy_lo) && fy_lo < f.y.hi) f.y.lo = fy_lo;
    if (std::isfinite(fy_hi) && fy_hi > f.y.lo) f.y.hi = fy_hi;
  }

  // y ticks: lane names, decades, or 1-2-5 steps.
  std::vector<double> y_ticks;
  std::vector<std::string> y_labels;
  if (timeline) {
    for (std::size_t i = 0; i < plot.lanes.size(); ++i) {
      y_ticks.push_back(f.y.hi - static_cast<double>(i) - 0.5);
      y_labels.push_back(plot.lanes[i].second);
    }
  } else {
    const Ticks yt = plot.log_y ? log_ticks(f.y.lo, f.y.hi) : make_ticks(f.y.lo, f.y.hi, 5.0);
    y_ticks = yt.values;
    for (const double v : yt.values)
      y_labels.push_back(plot.log_y ? log_tick_label(v) : tick_label(v, yt.step, f.y.lo, f.y.hi));
  }
  double longest = 0.0;
  for (const std::string& l : y_labels)
    longest = std::max(longest, text_width(l, text_style("tick")));
  // Room for the tick labels (8 px from the axis) and the rotated axis label (to x ≈ 19).
  f.left = std::max(60.0, 32.0 + longest);
  f.width = kWidth - f.left - kRight;
  if (has_points && !fixed_x) {  // keep markers at the ends whole
    const double pad = (f.x.hi - f.x.lo) * kEdgePad / f.width;
    f.x = {f.x.lo - pad, f.x.hi + pad};
  }

  // x ticks: as many as fit without their labels touching.
  Ticks xt;
  std::vector<std::string> x_labels;
  for (double target = 7.0; target >= 2.0; target -= 1.0) {
    xt = make_ticks(f.x.lo, f.x.hi, target);
    x_labels.clear();
    double widest = 0.0;
    for (const double v : xt.values) {
      x_labels.push_back(tick_label(v, xt.step, f.x.lo, f.x.hi));
      widest = std::max(widest, text_width(x_labels.back(), text_style("tick")));
    }
    const double spacing = xt.values.size() > 1 ? f.px(xt.values[1]) - f.px(xt.values[0]) : 1e9;
    if (widest + 10.0 < spacing) break;
  }

  // Legend layout: rows under the x-axis label, wrapped to the plot width.
  std::vector<LegendItem> legend;
  double lx = f.left;
  double rows = 0.0;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const std::string& name = plot.series[i].name;
    if (name.empty()) continue;
    const double w = 28.0 + text_width(name, text_style("legend")) + 24.0;
    if (legend.empty()) {
      rows = 1.0;
    } else if (lx + w > f.right() && lx > f.left) {
      lx = f.left;
      rows += 1.0;
    }
    legend.push_back({lx, rows - 1.0, i});
    lx += w;
  }

  // The data's footprint in pixels, for placing marker labels off it.
  Occupancy occ(f.left, f.top, f.width, f.height);
  for (std::size_t si = 0; si < series.size(); ++si) {
    if (timeline) continue;
    for (const Segment& seg : segments[si]) {
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
  std::string bands;
  for (std::size_t li = 0; timeline && li < plot.lanes.size(); ++li) {
    const double yc = f.py(y_ticks[li]);
    std::vector<std::pair<double, double>> px_runs;  // merged where closer than half a pixel
    for (const Series& s : series) {
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

  // Marker lines, in the plot area, and their labels beside them.
  std::vector<MarkerLabel> wanted;
  std::string marker_lines;
  for (const Marker& m : plot.markers) {
    if (!std::isfinite(m.x) || m.x < f.x.lo || m.x > f.x.hi) continue;
    const double x = f.px(m.x);
    marker_lines += line(x, f.top, x, f.bottom(), "m");
    occ.mark_line(x, f.top, x, f.bottom());
    wanted.push_back({x, m.label});
  }
  // The title is laid out first: marker labels may go in the strip between it and the frame.
  const Box title_box =
      text_box(f.left + f.width / 2.0, 24.0, "middle", false, plot.title, text_style("title"));
  std::vector<Box> taken{title_box};
  std::vector<std::string> unplaced;
  const Box frame_box{f.left, f.top, f.right(), f.bottom()};
  const Box above{4.0, title_box.y1 + 1.0, kWidth - 4.0, f.top};
  const std::vector<PlacedMarkerLabel> mlabels =
      place_marker_labels(wanted, frame_box, above, occ, taken, unplaced);

  const double legend_top = f.bottom() + 54.0;
  const double caption_rows = unplaced.empty() ? 0.0 : 1.0;
  const double height = rows + caption_rows > 0.0
                            ? legend_top + (rows + caption_rows) * kLegendRow + 6.0
                            : f.bottom() + 50.0;

  const TextWriter tw{placed};
  const std::string id = "clip" + std::to_string(plot_index);
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
  for (const double v : xt.values) {
    const double x = f.px(v);
    out += line(x, f.top, x, f.bottom(), "g");
  }
  for (const double v : y_ticks) {
    const double y = f.py(v);
    out += line(f.left, y, f.right(), y, "g");
  }
  out += "</g>\n<g class=\"ticks\">";
  for (std::size_t i = 0; i < xt.values.size(); ++i) {
    const double x = f.px(xt.values[i]);
    out += line(x, f.bottom(), x, f.bottom() + 5.0, "t");
    out += tw.text(x, f.bottom() + 19.0, "middle", "tick", x_labels[i]);
  }
  for (std::size_t i = 0; i < y_ticks.size(); ++i) {
    const double y = f.py(y_ticks[i]);
    out += line(f.left - 5.0, y, f.left, y, "t");
    out += tw.text(f.left - 8.0, y + 4.0, "end", "tick", y_labels[i]);
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

  // Markers: dashed vertical lines under the data; their labels (with a white halo) on top.
  out += "<g class=\"marker\">" + marker_lines + "</g>\n";

  // Series: timeline bands, or lines and points (each series drawn in its order, the last on
  // top).
  out += "<g clip-path=\"url(#" + id + ")\">\n" + bands;
  for (std::size_t si = 0; si < series.size() && !timeline; ++si) {
    const Series& s = series[si];
    const std::string color = color_of(s, si);
    if (s.points) {
      out += "<g class=\"points\" fill=\"" + color + "\">";
      for (const Segment& seg : segments[si]) {
        for (const Point& p : seg) {
          const double x = f.px(p.first), y = f.py(p.second);
          if (!std::isfinite(x) || !std::isfinite(y)) continue;
          out += "<circle cx=\"" + coord(x) + "\" cy=\"" + coord(y) + "\" r=\"2.6\"/>";
        }
      }
      out += "</g>\n";
      continue;
    }
    for (const Segment& seg : segments[si]) {
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
  out += "</g>\n";

  if (!mlabels.empty()) {
    out += "<g class=\"marker\">";
    for (const PlacedMarkerLabel& l : mlabels)
      out += l.rotated ? tw.rotated(l.x, l.y, l.anchor, "mark", l.text)
                       : tw.text(l.x, l.y, l.anchor, "mark", l.text);
    out += "</g>\n";
  }
  if (!has_data) {
    out += tw.text(f.left + f.width / 2.0, f.top + f.height / 2.0 + 6.0, "middle", "nodata",
                   "no data") +
           "\n";
  }

  // Legend (and, under it, the marker labels that found no room beside their lines).
  if (!legend.empty()) {
    out += "<g class=\"legend\">";
    for (const LegendItem& item : legend) {
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
    out += tw.text(f.left, legend_top + rows * kLegendRow, "", "legend", caption) + "\n";
  }
  out += "</svg>\n</figure>\n";
}

std::string series_color(const Series& s, std::size_t index) { return color_of(s, index); }

}  // namespace lathectl::io::detail
