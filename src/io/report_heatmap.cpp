// The report's heat map: one SVG of coloured cells over two category axes, a colour bar beside.
#include <algorithm>
#include <cmath>
#include <limits>

#include "report_plot.hpp"

namespace lathectl::io::detail {
namespace {

// Blue (0) → white (0.5) → red (1).
std::string colour(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const auto c = [](double v) { return std::to_string(static_cast<int>(std::lround(v * 255.0))); };
  if (t < 0.5) {
    const double u = t / 0.5;
    return "rgb(" + c(0.23 + 0.77 * u) + "," + c(0.36 + 0.64 * u) + "," + c(0.75 + 0.25 * u) + ")";
  }
  const double u = (t - 0.5) / 0.5;
  return "rgb(" + c(1.0 - 0.2 * u) + "," + c(1.0 - 0.8 * u) + "," + c(1.0 - 0.8 * u) + ")";
}

// The pixel of a value along an axis of cells: linear between the cells' centres (values
// strictly increasing), beyond the outer ones with their spacing; cell i spans [i, i + 1)·size.
double cell_position(const std::vector<double>& values, double v, double size) {
  const std::size_t n = values.size();
  if (n == 1) return 0.5 * size;
  std::size_t i = 1;
  while (i + 1 < n && v > values[i]) ++i;  // the segment [i − 1, i] holding v (or the outer one)
  const double frac = (v - values[i - 1]) / (values[i] - values[i - 1]);
  return (static_cast<double>(i - 1) + 0.5 + frac) * size;
}

bool increasing(const std::vector<double>& v, std::size_t n) {
  if (v.size() != n || n == 0) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i]) || (i > 0 && !(v[i] > v[i - 1]))) return false;
  return true;
}

// The lines over the map, in a nested <svg> (clipped to the map's cells) with the outer
// coordinates; their legend is returned for the caption.
std::string heat_map_lines(std::string& out, const HeatMap& m, double left, double top, double w,
                           double h, double cw, double ch) {
  if (m.lines.empty() || !increasing(m.x_values, m.xs.size()) ||
      !increasing(m.y_values, m.ys.size()))
    return {};
  out += "<svg x=\"" + coord(left) + "\" y=\"" + coord(top) + "\" width=\"" + coord(w) +
         "\" height=\"" + coord(h) + "\" viewBox=\"" + coord(left) + " " + coord(top) + " " +
         coord(w) + " " + coord(h) + "\" overflow=\"hidden\">\n";
  std::string legend;
  for (const HeatMapLine& l : m.lines) {
    std::string path;
    bool pen_down = false;
    for (std::size_t i = 0; i < l.x.size() && i < l.y.size(); ++i) {
      if (!std::isfinite(l.x[i]) || !std::isfinite(l.y[i])) {
        pen_down = false;
        continue;
      }
      const double px = left + cell_position(m.x_values, l.x[i], cw);
      const double py = top + h - cell_position(m.y_values, l.y[i], ch);
      if (!std::isfinite(px) || !std::isfinite(py)) continue;
      if (l.points) {
        out += "<circle cx=\"" + coord(px) + "\" cy=\"" + coord(py) + "\" r=\"3\" fill=\"" +
               l.color + "\" stroke=\"#fff\" stroke-width=\"0.8\"/>\n";
        continue;
      }
      path += (pen_down ? " L" : " M") + coord(px) + " " + coord(py);
      pen_down = true;
    }
    if (!path.empty())
      out += "<path d=\"" + path.substr(1) + "\" fill=\"none\" stroke=\"" + l.color +
             "\" stroke-width=\"2\"" + (l.dashed ? " stroke-dasharray=\"6 3\"" : "") + "/>\n";
    legend += "; <span style=\"color:" + l.color + "\">" +
              (l.points ? "●" : l.dashed ? "╌╌" : "━━") + "</span> " + escape(l.name);
  }
  out += "</svg>\n";
  return legend;
}

}  // namespace

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// The colour scale of a map: a value's place t in [0, 1] (NaN: no colour).
class ZScale {
 public:
  explicit ZScale(const HeatMap& m) : log_(m.log_z) {
    for (const auto& row : m.z)
      for (double v : row)
        if (std::isfinite(f(v))) lo = std::min(lo, v), hi = std::max(hi, v);
    centre_ = f(m.z_centre);
  }
  [[nodiscard]] double f(double v) const { return log_ ? (v > 0.0 ? std::log10(v) : kNoValue) : v; }
  [[nodiscard]] double t(double v) const {
    const double x = f(v), a = f(lo), b = f(hi);
    if (!std::isfinite(x)) return kNoValue;
    if (!std::isfinite(centre_)) return (x - a) / (b > a ? b - a : 1.0);
    if (x < centre_) return centre_ > a ? 0.5 * (x - a) / (centre_ - a) : 0.0;
    return b > centre_ ? 0.5 + 0.5 * (x - centre_) / (b - centre_) : 1.0;
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;

 private:
  bool log_;
  double centre_;
};

void render_heat_map(std::string& out, const HeatMap& m) {
  const ZScale scale(m);
  const double lo = scale.lo, hi = scale.hi;
  const double left = 90, top = 30, cw = std::max(18.0, 560.0 / double(std::max<std::size_t>(1, m.xs.size())));
  const double ch = std::max(14.0, 300.0 / double(std::max<std::size_t>(1, m.ys.size())));
  const double w = cw * double(m.xs.size()), h = ch * double(m.ys.size());
  const double width = left + w + 110, height = top + h + 60;
  out += "<figure class=\"plot heatmap\"><figcaption>" + escape(m.title) + "</figcaption>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " + coord(width) + " " +
         coord(height) + "\" width=\"" + coord(width) + "\" height=\"" + coord(height) +
         "\" role=\"img\">\n";
  for (std::size_t iy = 0; iy < m.ys.size(); ++iy) {
    const double y = top + h - ch * double(iy + 1);  // the first y at the bottom
    for (std::size_t ix = 0; ix < m.xs.size(); ++ix) {
      const double v = iy < m.z.size() && ix < m.z[iy].size()
                           ? m.z[iy][ix]
                           : std::numeric_limits<double>::quiet_NaN();
      const double t = scale.t(v);
      const std::string fill = std::isfinite(t) ? colour(t) : "#bbb";
      out += "<rect x=\"" + coord(left + cw * double(ix)) + "\" y=\"" + coord(y) + "\" width=\"" +
             coord(cw) + "\" height=\"" + coord(ch) + "\" fill=\"" + fill + "\"><title>" +
             escape(m.x_label + " = " + m.xs[ix] + ", " + m.y_label + " = " + m.ys[iy] + ": " +
                    (std::isfinite(v) ? general(v, 6) : std::string("no value"))) +
             "</title></rect>\n";
    }
    out += "<text class=\"tick\" x=\"" + coord(left - 4) + "\" y=\"" + coord(y + ch / 2 + 4) +
           "\" text-anchor=\"end\">" + escape(m.ys[iy]) + "</text>\n";
  }
  double widest = 0.0;  // the column labels that fit side by side: every k-th
  for (const auto& x : m.xs) widest = std::max(widest, text_width(x, text_style("tick")));
  const std::size_t every = std::max<std::size_t>(
      {1, m.xs.size() / 12, static_cast<std::size_t>(std::ceil((widest + 6.0) / cw))});
  for (std::size_t ix = 0; ix < m.xs.size(); ix += every)
    out += "<text class=\"tick\" x=\"" + coord(left + cw * (double(ix) + 0.5)) + "\" y=\"" +
           coord(top + h + 14) + "\" text-anchor=\"middle\">" + escape(m.xs[ix]) + "</text>\n";
  out += "<text class=\"axis-label\" x=\"" + coord(left + w / 2) + "\" y=\"" + coord(top + h + 36) +
         "\" text-anchor=\"middle\">" + escape(m.x_label) + "</text>\n";
  out += "<text class=\"axis-label\" x=\"12\" y=\"" + coord(top + h / 2) +
         "\" text-anchor=\"middle\" transform=\"rotate(-90 12 " + coord(top + h / 2) + ")\">" +
         escape(m.y_label) + "</text>\n";
  const double bx = left + w + 20;  // the colour bar, lowest at the bottom
  for (int i = 0; i < 20; ++i)
    out += "<rect x=\"" + coord(bx) + "\" y=\"" + coord(top + h - h * (i + 1) / 20.0) +
           "\" width=\"14\" height=\"" + coord(h / 20.0 + 0.5) + "\" fill=\"" +
           colour((i + 0.5) / 20.0) + "\"/>\n";
  const std::string legend = heat_map_lines(out, m, left, top, w, h, cw, ch);
  if (std::isfinite(lo)) {
    out += "<text class=\"tick\" x=\"" + coord(bx + 18) + "\" y=\"" + coord(top + h) + "\">" +
           escape(general(lo, 4)) + "</text>\n";
    out += "<text class=\"tick\" x=\"" + coord(bx + 18) + "\" y=\"" + coord(top + 10) + "\">" +
           escape(general(hi, 4)) + "</text>\n";
    if (std::isfinite(scale.f(m.z_centre)) && m.z_centre > lo && m.z_centre < hi)
      out += "<text class=\"tick\" x=\"" + coord(bx + 18) + "\" y=\"" + coord(top + h / 2 + 4) +
             "\">" + escape(general(m.z_centre, 4)) + "</text>\n";
  }
  out += "</svg><figcaption>colour: " + escape(m.z_label) + (m.log_z ? ", logarithmic" : "") +
         " (grey: no value)" + legend +
         "</figcaption></figure>\n";
}

}  // namespace lathectl::io::detail
