#include "lathectl/io/report.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace lathectl::io {
namespace {

// ---------------------------------------------------------------------------------------------
// Text and number formatting

// Eight colours that stay distinguishable on white and for the common colour-vision deficiencies
// as far as eight can.
constexpr std::string_view kPalette[] = {"#2563eb", "#dc2626", "#16a34a", "#ea580c",
                                         "#7c3aed", "#0891b2", "#a16207", "#db2777"};
constexpr std::size_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

// Values beyond this are clamped before scaling so that ranges and pixel maths stay finite.
constexpr double kHuge = 1e300;

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

// <ul class="cls"> of the links (each a plain item when it has no href); nothing when empty.
void link_list(std::string& out, const std::vector<Link>& links, const char* cls) {
  if (links.empty()) return;
  out += std::string("<ul class=\"") + cls + "\">\n";
  for (const auto& l : links) {
    out += "<li>";
    out += l.href.empty() ? escape(l.text)
                          : "<a href=\"" + escape(l.href) + "\">" + escape(l.text) + "</a>";
    out += "</li>\n";
  }
  out += "</ul>\n";
}

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

// Number of characters (UTF-8 code points), for rough text width estimates.
std::size_t text_length(std::string_view s) {
  std::size_t n = 0;
  for (const char c : s) {
    if ((static_cast<unsigned char>(c) & 0xC0U) != 0x80U) ++n;
  }
  return n;
}

double text_width(std::string_view s, double px_per_char) {
  return static_cast<double>(text_length(s)) * px_per_char;
}

// A table cell that starts with a number (optionally followed by a unit) is right-aligned.
bool looks_numeric(std::string_view s) {
  if (s.empty()) return false;
  std::size_t i = 0;
  if (s[0] == '+' || s[0] == '-') i = 1;
  if (i >= s.size()) return false;
  const auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
  if (!is_digit(s[i]) && !(s[i] == '.' && i + 1 < s.size() && is_digit(s[i + 1]))) return false;
  double value = 0.0;
  const char* first = s.data() + (s[0] == '+' ? 1 : 0);
  const auto r = std::from_chars(first, s.data() + s.size(), value);
  if (r.ec != std::errc{}) return false;
  return r.ptr == s.data() + s.size() || *r.ptr == ' ';
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
// Decimation

using Point = std::pair<double, double>;
using Segment = std::vector<Point>;  // a run of finite points, drawn as one polyline

bool finite_point(const Series& s, std::size_t i) {
  return std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
}

// Splits the series into runs of finite points. If it has more than max_points finite points,
// each of max_points/2 index buckets contributes only its minimum and maximum (in index order),
// so spikes survive decimation.
std::vector<Segment> segments_of(const Series& s, std::size_t max_points) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (finite_point(s, i)) ++finite;
  }
  max_points = std::max<std::size_t>(max_points, 2);
  std::size_t bucket = 1;
  if (finite > max_points) {
    const std::size_t buckets = max_points / 2;
    bucket = (n + buckets - 1) / buckets;
  }

  std::vector<Segment> out;
  Segment current;
  bool run = false;
  std::size_t i_min = 0;
  std::size_t i_max = 0;
  const auto flush_run = [&] {
    if (!run) return;
    const Point a{s.x[std::min(i_min, i_max)], s.y[std::min(i_min, i_max)]};
    current.push_back(a);
    if (i_min != i_max)
      current.emplace_back(s.x[std::max(i_min, i_max)], s.y[std::max(i_min, i_max)]);
    run = false;
  };
  const auto break_line = [&] {
    flush_run();
    if (!current.empty()) out.push_back(std::move(current));
    current.clear();
  };

  for (std::size_t b = 0; b < n; b += bucket) {
    const std::size_t end = std::min(n, b + bucket);
    for (std::size_t i = b; i < end; ++i) {
      if (!finite_point(s, i)) {
        break_line();
        continue;
      }
      if (!run) {
        i_min = i_max = i;
        run = true;
      } else {
        if (s.y[i] < s.y[i_min]) i_min = i;
        if (s.y[i] > s.y[i_max]) i_max = i;
      }
    }
    flush_run();
  }
  break_line();
  return out;
}

// ---------------------------------------------------------------------------------------------
// SVG plot

constexpr double kWidth = 900.0;
constexpr double kTop = 44.0;  // plot area top (title above)
constexpr double kPlotHeight = 212.0;
constexpr double kRight = 24.0;
constexpr double kLegendRow = 20.0;
constexpr double kCharWidth = 7.0;  // rough width of a 12 px character

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

std::string text(double x, double y, std::string_view anchor, std::string_view cls,
                 std::string_view content) {
  std::string out = "<text x=\"" + coord(x) + "\" y=\"" + coord(y) + "\"";
  if (!anchor.empty()) out += " text-anchor=\"" + std::string(anchor) + "\"";
  if (!cls.empty()) out += " class=\"" + std::string(cls) + "\"";
  out += ">" + escape(content) + "</text>";
  return out;
}

struct LegendItem {
  double x = 0.0;
  double row = 0.0;
  std::size_t series = 0;
};

void render_plot(std::string& out, const Plot& plot, std::size_t plot_index,
                 std::size_t max_points) {
  // Decimated runs of finite points per series, and the data extent (from all finite points,
  // not only the kept ones, so the axes are the same with or without decimation).
  std::vector<std::vector<Segment>> segments;
  segments.reserve(plot.series.size());
  bool has_data = false;
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
  for (const Series& s : plot.series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (!finite_point(s, i)) continue;
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
  f.x = widen(x_lo, x_hi, 0.0);
  f.y = has_data ? widen(y_lo, y_hi, 0.05) : Range{0.0, 1.0};
  const Ticks xt = make_ticks(f.x.lo, f.x.hi, 7.0);
  const Ticks yt = make_ticks(f.y.lo, f.y.hi, 5.0);
  std::vector<std::string> y_labels;
  std::size_t longest = 1;
  for (const double v : yt.values) {
    y_labels.push_back(tick_label(v, yt.step, f.y.lo, f.y.hi));
    longest = std::max(longest, text_length(y_labels.back()));
  }
  f.left = std::max(60.0, 36.0 + static_cast<double>(longest) * kCharWidth);
  f.width = kWidth - f.left - kRight;

  // Legend layout: rows under the x-axis label, wrapped to the plot width.
  std::vector<LegendItem> legend;
  double lx = f.left;
  double rows = 0.0;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const std::string& name = plot.series[i].name;
    if (name.empty()) continue;
    const double w = 30.0 + text_width(name, kCharWidth) + 22.0;
    if (legend.empty()) {
      rows = 1.0;
    } else if (lx + w > f.right() && lx > f.left) {
      lx = f.left;
      rows += 1.0;
    }
    legend.push_back({lx, rows - 1.0, i});
    lx += w;
  }
  const double legend_top = f.bottom() + 54.0;
  const double height = rows > 0.0 ? legend_top + rows * kLegendRow + 6.0 : f.bottom() + 50.0;

  const std::string id = "clip" + std::to_string(plot_index);
  out += "<figure class=\"plot\">\n<svg class=\"chart\" viewBox=\"0 0 " + coord(kWidth) + " " +
         coord(height) + "\" role=\"img\" aria-label=\"" + escape(plot.title) + "\">\n";
  out += "<defs><clipPath id=\"" + id + "\"><rect x=\"" + coord(f.left - 4.0) + "\" y=\"" +
         coord(f.top - 4.0) + "\" width=\"" + coord(f.width + 8.0) + "\" height=\"" +
         coord(f.height + 8.0) + "\"/></clipPath></defs>\n";
  out += text(f.left + f.width / 2.0, 24.0, "middle", "title", plot.title) + "\n";
  out += "<rect class=\"frame\" x=\"" + coord(f.left) + "\" y=\"" + coord(f.top) + "\" width=\"" +
         coord(f.width) + "\" height=\"" + coord(f.height) + "\"/>\n";

  // Grid and tick labels.
  out += "<g class=\"grid\">";
  for (const double v : xt.values) {
    const double x = f.px(v);
    out += line(x, f.top, x, f.bottom(), "g");
  }
  for (const double v : yt.values) {
    const double y = f.py(v);
    out += line(f.left, y, f.right(), y, "g");
  }
  out += "</g>\n<g class=\"ticks\">";
  for (const double v : xt.values) {
    const double x = f.px(v);
    out += line(x, f.bottom(), x, f.bottom() + 5.0, "t");
    out += text(x, f.bottom() + 19.0, "middle", "", tick_label(v, xt.step, f.x.lo, f.x.hi));
  }
  for (std::size_t i = 0; i < yt.values.size(); ++i) {
    const double y = f.py(yt.values[i]);
    out += line(f.left - 5.0, y, f.left, y, "t");
    out += text(f.left - 8.0, y + 4.0, "end", "", y_labels[i]);
  }
  out += "</g>\n";
  out += line(f.left, f.top, f.left, f.bottom(), "axis") +
         line(f.left, f.bottom(), f.right(), f.bottom(), "axis") + "\n";

  // Axis labels.
  if (!plot.x_label.empty()) {
    out += text(f.left + f.width / 2.0, f.bottom() + 40.0, "middle", "label", plot.x_label) + "\n";
  }
  if (!plot.y_label.empty()) {
    const double cy = f.top + f.height / 2.0;
    out += "<text transform=\"translate(16 " + coord(cy) +
           ") rotate(-90)\" text-anchor=\"middle\" class=\"label\">" + escape(plot.y_label) +
           "</text>\n";
  }

  // Markers: dashed vertical lines under the data; their labels (rotated, reading upwards from
  // the top, with a white halo) go on top of the data so they stay legible.
  std::string marker_labels;
  out += "<g class=\"marker\">";
  for (const Marker& m : plot.markers) {
    if (!std::isfinite(m.x) || m.x < f.x.lo || m.x > f.x.hi) continue;
    const double x = f.px(m.x);
    out += line(x, f.top, x, f.bottom(), "m");
    if (!m.label.empty()) {
      marker_labels += "<text transform=\"translate(" + coord(x - 4.0) + " " + coord(f.top + 6.0) +
                       ") rotate(-90)\" text-anchor=\"end\">" + escape(m.label) + "</text>";
    }
  }
  out += "</g>\n";

  // Series.
  out += "<g clip-path=\"url(#" + id + ")\">\n";
  for (std::size_t si = 0; si < plot.series.size(); ++si) {
    const Series& s = plot.series[si];
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

  if (!marker_labels.empty()) out += "<g class=\"marker\">" + marker_labels + "</g>\n";
  if (!has_data) {
    out +=
        text(f.left + f.width / 2.0, f.top + f.height / 2.0 + 6.0, "middle", "nodata", "no data") +
        "\n";
  }

  // Legend.
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
      out += text(item.x + 28.0, y, "", "", s.name);
    }
    out += "</g>\n";
  }
  out += "</svg>\n</figure>\n";
}

// ---------------------------------------------------------------------------------------------
// Page

constexpr std::string_view kStyle = R"css(
:root { color-scheme: light; }
* { box-sizing: border-box; }
body { margin: 0; background: #f3f4f6; color: #1f2328;
  font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial,
    "Noto Sans", "Liberation Sans", sans-serif; }
main { max-width: 980px; margin: 0 auto; padding: 28px 18px 40px; }
header { margin-bottom: 8px; }
h1 { font-size: 26px; line-height: 1.25; margin: 0 0 4px; font-weight: 650; }
.subtitle { color: #59636e; margin: 0; }
h2 { font-size: 16px; margin: 0 0 10px; font-weight: 620; color: #24292f; }
section { background: #fff; border: 1px solid #d8dee4; border-radius: 8px;
  padding: 16px 20px; margin: 16px 0; }
section.description { background: transparent; border: 0; padding: 0; }
section.description p { margin: 8px 0; max-width: 75ch; }
.table-wrap { overflow-x: auto; }
table { border-collapse: collapse; font-size: 14px; font-variant-numeric: tabular-nums; }
table.data { min-width: 60%; }
th, td { padding: 5px 12px; border-bottom: 1px solid #e5e8eb; text-align: left;
  vertical-align: top; }
th { background: #f6f8fa; font-weight: 600; border-bottom: 1px solid #d0d7de; }
tbody tr:nth-child(even) td { background: #fafbfc; }
th.num, td.num { text-align: right; white-space: nowrap; }
table.metrics td:first-child { color: #424a53; padding-right: 32px; }
table.metrics th:last-child { text-align: right; }
table.metrics td:last-child { font-weight: 600; text-align: right; white-space: nowrap; }
ul.notes { margin: 0; padding-left: 20px; }
ul.notes li { margin: 4px 0; }
figure.plot { margin: 0 0 18px; }
figure.plot:last-child { margin-bottom: 0; }
svg.chart { display: block; width: 100%; height: auto; }
svg.chart text { font-family: inherit; font-size: 12px; fill: #424a53; }
svg.chart text.title { font-size: 15px; font-weight: 600; fill: #1f2328; }
svg.chart text.label { font-size: 13px; fill: #24292f; }
svg.chart text.nodata { font-size: 16px; fill: #8c959f; }
svg.chart .frame { fill: #fff; stroke: none; }
svg.chart .grid line { stroke: #e6e9ed; stroke-width: 1; }
svg.chart .ticks line { stroke: #8c959f; stroke-width: 1; }
svg.chart line.axis { stroke: #57606a; stroke-width: 1.2; }
svg.chart .marker line { stroke: #8c959f; stroke-width: 1.2; stroke-dasharray: 4 3; }
svg.chart .marker text { font-size: 11px; fill: #57606a; paint-order: stroke; stroke: #fff;
  stroke-width: 3px; stroke-linejoin: round; }
ul.index { list-style: none; margin: 0; padding: 0; }
ul.index li { padding: 10px 0; border-bottom: 1px solid #e5e8eb; }
ul.index li:last-child { border-bottom: 0; }
ul.index a { font-weight: 600; color: #0b57d0; text-decoration: none; }
ul.index a:hover { text-decoration: underline; }
ul.index .summary { display: block; color: #59636e; font-size: 14px;
  font-variant-numeric: tabular-nums; }
section.verdict.ok { border-color: #16a34a; }
section.verdict.bad { border-color: #dc2626; }
.verdict .mark, ul.index .mark { font-weight: 700; }
.ok .mark, ul.index .ok { color: #16a34a; }
.bad .mark, ul.index .bad { color: #dc2626; }
ul.index ul.problems { margin: 4px 0 0; padding-left: 20px; font-size: 14px; }
ul.index ul.problems a { font-weight: 400; }
li:target { background: #fff3c4; }
footer { color: #8c959f; font-size: 12px; margin-top: 24px; }
@media print { body { background: #fff; } section { break-inside: avoid; } }
)css";

void begin_page(std::string& out, std::string_view title) {
  out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + escape(title) + "</title>\n<style>";
  out += kStyle;
  out += "</style>\n</head>\n<body>\n<main>\n";
}

// Where the documentation lives: docs/ in the sources, this directory once installed.
constexpr std::string_view kInstalledDocs = "/usr/share/doc/lathectl/docs/";

void end_page(std::string& out, std::string_view doc_page) {
  const std::string page = doc_page.empty() ? std::string("README.md") : std::string(doc_page);
  out += "<footer>Generated by lathectl. Self-contained page: no scripts, no network.<br>\n";
  out += doc_page.empty()
             ? std::string(
                   "Seed numbers (000–004), formula numbers such as (23) and block numbers "
                   "such as “sensor 4” refer to the five original documents")
             : std::string(
                   "Seed, formula and block numbers in this report refer to the original "
                   "document");
  out += ", summarised in docs/" + escape(page) +
         " of the lathectl sources (installed: " + std::string(kInstalledDocs) + escape(page) +
         ").</footer>\n";
  out += "</main>\n</body>\n</html>\n";
}

// Paragraphs separated by blank (or whitespace-only) lines.
std::vector<std::string> paragraphs(std::string_view text_in) {
  std::vector<std::string> out;
  std::string current;
  std::size_t pos = 0;
  while (pos <= text_in.size()) {
    const std::size_t nl = std::min(text_in.find('\n', pos), text_in.size());
    std::string_view ln = text_in.substr(pos, nl - pos);
    if (!ln.empty() && ln.back() == '\r') ln.remove_suffix(1);
    if (ln.find_first_not_of(" \t") == std::string_view::npos) {
      if (!current.empty()) out.push_back(std::move(current));
      current.clear();
    } else {
      if (!current.empty()) current += '\n';
      current += ln;
    }
    pos = nl + 1;
  }
  if (!current.empty()) out.push_back(std::move(current));
  return out;
}

// A placeholder such as "—", "-" or "" (no letters or digits) does not decide a column's type.
bool is_placeholder(std::string_view s) {
  for (const char c : s) {
    if ((c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) return false;
  }
  return true;
}

// Columns whose cells are all numbers (optionally with a unit) are right-aligned, header included.
std::vector<bool> numeric_columns(const Table& table) {
  std::size_t columns = table.header.size();
  for (const auto& row : table.rows) columns = std::max(columns, row.size());
  std::vector<bool> numeric(columns, false);
  for (std::size_t c = 0; c < columns; ++c) {
    bool any = false;
    bool all = true;
    for (const auto& row : table.rows) {
      if (c >= row.size() || is_placeholder(row[c])) continue;
      if (looks_numeric(row[c])) {
        any = true;
      } else {
        all = false;
      }
    }
    numeric[c] = any && all;
  }
  return numeric;
}

void render_table(std::string& out, const Table& table) {
  const std::vector<bool> numeric = numeric_columns(table);
  out += "<section class=\"table\">\n";
  if (!table.title.empty()) out += "<h2>" + escape(table.title) + "</h2>\n";
  out += "<div class=\"table-wrap\"><table class=\"data\">\n";
  if (!table.header.empty()) {
    out += "<thead><tr>";
    for (std::size_t c = 0; c < table.header.size(); ++c) {
      out += numeric[c] ? "<th class=\"num\">" : "<th>";
      out += escape(table.header[c]) + "</th>";
    }
    out += "</tr></thead>\n";
  }
  out += "<tbody>\n";
  for (const auto& row : table.rows) {
    out += "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c) {
      out += numeric[c] ? "<td class=\"num\">" : "<td>";
      out += escape(row[c]) + "</td>";
    }
    for (std::size_t c = row.size(); c < table.header.size(); ++c) out += "<td></td>";
    out += "</tr>\n";
  }
  out += "</tbody></table></div>\n</section>\n";
}

}  // namespace

std::string render_html(const Report& report, std::size_t max_points) {
  std::string out;
  out.reserve(64 * 1024);
  begin_page(out, report.title);

  out += "<header>\n<h1>" + escape(report.title) + "</h1>\n";
  if (!report.subtitle.empty())
    out += "<p class=\"subtitle\">" + escape(report.subtitle) + "</p>\n";
  out += "</header>\n";

  const std::vector<std::string> paras = paragraphs(report.description);
  if (!paras.empty()) {
    out += "<section class=\"description\">\n";
    for (const std::string& p : paras) out += "<p>" + escape(p) + "</p>\n";
    out += "</section>\n";
  }

  if (!report.verdict.empty()) {
    out += std::string("<section class=\"verdict ") + (report.verdict_ok ? "ok" : "bad") +
           "\" id=\"verdict\">\n<h2>Verdict</h2>\n<p class=\"mark\">" + escape(report.verdict) +
           "</p>\n";
    link_list(out, report.verdict_items, "notes");
    out += "</section>\n";
  }

  if (!report.metrics.empty()) {
    out += "<section class=\"metrics\">\n<h2>Metrics</h2>\n<div class=\"table-wrap\">";
    out += "<table class=\"metrics\">\n<thead><tr><th>Metric</th><th>Value</th></tr></thead>\n";
    out += "<tbody>\n";
    for (const auto& [name, value] : report.metrics) {
      out += "<tr><td>" + escape(name) + "</td><td>" + escape(value) + "</td></tr>\n";
    }
    out += "</tbody></table></div>\n</section>\n";
  }

  if (!report.notes.empty()) {
    out += "<section class=\"notes\">\n<h2>Notes</h2>\n<ul class=\"notes\">\n";
    for (std::size_t i = 0; i < report.notes.size(); ++i) {
      const bool id = i < report.note_ids.size() && !report.note_ids[i].empty();
      out += id ? "<li id=\"" + escape(report.note_ids[i]) + "\">" : std::string("<li>");
      out += escape(report.notes[i]) + "</li>\n";
    }
    out += "</ul>\n</section>\n";
  }

  for (const Table& t : report.tables) render_table(out, t);

  if (!report.plots.empty()) {
    out += "<section class=\"plots\">\n<h2>Plots</h2>\n";
    for (std::size_t i = 0; i < report.plots.size(); ++i) {
      render_plot(out, report.plots[i], i, max_points);
    }
    out += "</section>\n";
  }

  end_page(out, report.doc_page);
  return out;
}

std::string render_index_html(const std::string& title, const std::vector<IndexEntry>& entries) {
  std::string out;
  begin_page(out, title);
  out += "<header>\n<h1>" + escape(title) + "</h1>\n</header>\n<section class=\"index\">\n";
  if (entries.empty()) {
    out += "<p>No reports.</p>\n";
  } else {
    out += "<ul class=\"index\">\n";
    for (const IndexEntry& e : entries) {
      const std::string& label = e.title.empty() ? e.href : e.title;
      out += "<li>";
      if (e.status != 0)
        out += std::string("<span class=\"mark ") + (e.status > 0 ? "ok\">✔" : "bad\">✘") +
               "</span> ";
      out += "<a href=\"" + escape(e.href) + "\">" + escape(label) + "</a>";
      if (!e.summary.empty()) out += "<span class=\"summary\">" + escape(e.summary) + "</span>";
      if (!e.verdict.empty())
        out += std::string("<span class=\"summary ") + (e.status < 0 ? "bad" : "ok") + "\">" +
               escape(e.verdict) + "</span>";
      link_list(out, e.problems, "problems");
      out += "</li>\n";
    }
    out += "</ul>\n";
  }
  out += "</section>\n";
  end_page(out, {});
  return out;
}

}  // namespace lathectl::io
