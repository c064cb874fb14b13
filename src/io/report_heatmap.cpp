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

}  // namespace

void render_heat_map(std::string& out, const HeatMap& m) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& row : m.z)
    for (double v : row)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  const double span = hi > lo ? hi - lo : 1.0;
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
      const std::string fill = std::isfinite(v) ? colour((v - lo) / span) : "#bbb";
      out += "<rect x=\"" + coord(left + cw * double(ix)) + "\" y=\"" + coord(y) + "\" width=\"" +
             coord(cw) + "\" height=\"" + coord(ch) + "\" fill=\"" + fill + "\"><title>" +
             escape(m.x_label + " = " + m.xs[ix] + ", " + m.y_label + " = " + m.ys[iy] + ": " +
                    (std::isfinite(v) ? general(v, 6) : std::string("no value"))) +
             "</title></rect>\n";
    }
    out += "<text class=\"tick\" x=\"" + coord(left - 4) + "\" y=\"" + coord(y + ch / 2 + 4) +
           "\" text-anchor=\"end\">" + escape(m.ys[iy]) + "</text>\n";
  }
  const std::size_t every = std::max<std::size_t>(1, m.xs.size() / 12);
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
  if (std::isfinite(lo)) {
    out += "<text class=\"tick\" x=\"" + coord(bx + 18) + "\" y=\"" + coord(top + h) + "\">" +
           escape(general(lo, 4)) + "</text>\n";
    out += "<text class=\"tick\" x=\"" + coord(bx + 18) + "\" y=\"" + coord(top + 10) + "\">" +
           escape(general(hi, 4)) + "</text>\n";
  }
  out += "</svg><figcaption>colour: " + escape(m.z_label) + " (grey: no value)</figcaption></figure>\n";
}

}  // namespace lathectl::io::detail
