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

}  // namespace

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

std::string series_color(const Series& s, std::size_t index) { return color_of(s, index); }

}  // namespace lathectl::io::detail
