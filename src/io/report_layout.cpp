// Text metrics of the report's SVG plots and the placement of marker labels (report_plot.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "report_plot.hpp"

namespace lathectl::io::detail {

namespace {

// Advance widths [em] of DejaVu Sans Book, U+0020..U+007E (from the font's hmtx table).
constexpr double kAsciiEm[95] = {
    0.318, 0.401, 0.460, 0.838, 0.636, 0.950, 0.780, 0.275, 0.390, 0.390, 0.500, 0.838,
    0.318, 0.361, 0.318, 0.337, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636,
    0.636, 0.636, 0.337, 0.337, 0.838, 0.838, 0.838, 0.531, 1.000, 0.684, 0.686, 0.698,
    0.770, 0.632, 0.575, 0.775, 0.752, 0.295, 0.295, 0.656, 0.557, 0.863, 0.748, 0.787,
    0.603, 0.787, 0.695, 0.635, 0.611, 0.732, 0.684, 0.989, 0.685, 0.611, 0.685, 0.390,
    0.337, 0.390, 0.838, 0.500, 0.500, 0.613, 0.635, 0.550, 0.635, 0.615, 0.352, 0.635,
    0.634, 0.278, 0.278, 0.579, 0.278, 0.974, 0.634, 0.612, 0.635, 0.635, 0.411, 0.521,
    0.392, 0.634, 0.592, 0.818, 0.592, 0.592, 0.525, 0.636, 0.337, 0.636, 0.838};
constexpr double kLetterEm = 0.70;    // other characters below U+2000 (Latin-1, Greek)
constexpr double kSymbolEm = 0.84;    // the rest (−, ×, ≈, arrows …)
constexpr double kBoldFactor = 1.11;  // DejaVu Sans Bold / Book, mean over ASCII

// Decodes one UTF-8 code point at s[i], advancing i (invalid bytes count as one character).
char32_t next_code_point(std::string_view s, std::size_t& i) {
  const auto b = static_cast<unsigned char>(s[i++]);
  if (b < 0x80U) return b;
  int extra = (b & 0xE0U) == 0xC0U ? 1 : (b & 0xF0U) == 0xE0U ? 2 : (b & 0xF8U) == 0xF0U ? 3 : 0;
  char32_t cp = extra == 1 ? (b & 0x1FU) : extra == 2 ? (b & 0x0FU) : (b & 0x07U);
  for (; extra > 0 && i < s.size(); --extra) {
    const auto c = static_cast<unsigned char>(s[i]);
    if ((c & 0xC0U) != 0x80U) break;
    cp = (cp << 6) | (c & 0x3FU);
    ++i;
  }
  return cp;
}

}  // namespace

TextStyle text_style(std::string_view cls) {
  if (cls == "title") return {15.0, true};
  if (cls == "label") return {13.0, false};
  if (cls == "nodata") return {16.0, false};
  if (cls == "mark") return {11.0, false};
  return {12.0, false};  // tick, legend
}

double text_width(std::string_view s, const TextStyle& style) {
  double em = 0.0;
  for (std::size_t i = 0; i < s.size();) {
    const char32_t cp = next_code_point(s, i);
    if (cp >= 0x20 && cp < 0x7F) {
      em += kAsciiEm[cp - 0x20];
    } else {
      em += cp < 0x2000 ? kLetterEm : kSymbolEm;
    }
  }
  return em * style.px * (style.bold ? kBoldFactor : 1.0);
}

bool Box::overlaps(const Box& o, double slack) const {
  return std::min(x1, o.x1) - std::max(x0, o.x0) > slack &&
         std::min(y1, o.y1) - std::max(y0, o.y0) > slack;
}

bool Box::inside(const Box& o, double slack) const {
  return x0 >= o.x0 - slack && y0 >= o.y0 - slack && x1 <= o.x1 + slack && y1 <= o.y1 + slack;
}

Box text_box(double x, double y, std::string_view anchor, bool rotated, std::string_view text,
             const TextStyle& style) {
  const double w = text_width(text, style);
  const double start = anchor == "middle" ? -w / 2.0 : anchor == "end" ? -w : 0.0;
  const double up = 0.76 * style.px, down = 0.24 * style.px;
  if (!rotated) return {x + start, y - up, x + start + w, y + down};
  // rotate(−90): the text runs upwards from (x, y); "above the baseline" is to the left.
  return {x - up, y - start - w, x + down, y - start};
}

Occupancy::Occupancy(double left, double top, double width, double height)
    : left_(left),
      top_(top),
      nx_(static_cast<std::size_t>(std::max(1.0, std::ceil(width / kCell)))),
      ny_(static_cast<std::size_t>(std::max(1.0, std::ceil(height / kCell)))),
      cells_(nx_ * ny_, 0) {}

void Occupancy::mark_point(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  const double cx = std::floor((x - left_) / kCell), cy = std::floor((y - top_) / kCell);
  if (cx < 0.0 || cy < 0.0 || cx >= static_cast<double>(nx_) || cy >= static_cast<double>(ny_))
    return;
  cells_[static_cast<std::size_t>(cy) * nx_ + static_cast<std::size_t>(cx)] = 1;
}

void Occupancy::mark_line(double x0, double y0, double x1, double y1) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  // Clip the step count: a line far outside the frame (a clipped series) costs nothing.
  const double len = std::min(std::hypot(x1 - x0, y1 - y0), 4000.0);
  const int steps = static_cast<int>(std::ceil(len / (kCell * 0.5)));
  for (int k = 0; k <= steps; ++k) {
    const double u = steps > 0 ? static_cast<double>(k) / steps : 0.0;
    mark_point(x0 + (x1 - x0) * u, y0 + (y1 - y0) * u);
  }
}

void Occupancy::mark_rect(double x0, double y0, double x1, double y1) {
  for (double y = y0; y <= y1; y += kCell * 0.5)
    for (double x = x0; x <= x1; x += kCell * 0.5) mark_point(x, y);
}

std::size_t Occupancy::count(const Box& b) const {
  const auto clampi = [](double v, std::size_t n) {
    return static_cast<std::size_t>(std::clamp(v, 0.0, static_cast<double>(n)));
  };
  const std::size_t i0 = clampi(std::floor((b.x0 - left_) / kCell), nx_);
  const std::size_t i1 = clampi(std::ceil((b.x1 - left_) / kCell), nx_);
  const std::size_t j0 = clampi(std::floor((b.y0 - top_) / kCell), ny_);
  const std::size_t j1 = clampi(std::ceil((b.y1 - top_) / kCell), ny_);
  std::size_t n = 0;
  for (std::size_t j = j0; j < j1; ++j)
    for (std::size_t i = i0; i < i1; ++i) n += cells_[j * nx_ + i];
  return n;
}

std::vector<PlacedMarkerLabel> place_marker_labels(const std::vector<MarkerLabel>& labels,
                                                   const Box& frame, const Box& above,
                                                   const Occupancy& occ, std::vector<Box>& placed,
                                                   std::vector<std::string>& unplaced) {
  const TextStyle style = text_style("mark");
  constexpr double kGap = 4.0;    // from the line
  constexpr double kInset = 6.0;  // from the frame's top or bottom
  constexpr int kHeights = 5;     // positions along the line, top to bottom
  std::vector<PlacedMarkerLabel> out;
  for (const MarkerLabel& m : labels) {
    if (m.text.empty()) continue;
    const bool named = std::any_of(out.begin(), out.end(), [&](const PlacedMarkerLabel& p) {
      return p.text == m.text && std::abs(p.line_x - m.x) < 40.0;
    });
    if (named) continue;
    const double w = text_width(m.text, style);
    const double travel = frame.y1 - frame.y0 - 2.0 * kInset - w;
    bool found = false;
    double best_cost = 0.0;
    PlacedMarkerLabel best;
    for (int side = 0; side < 2; ++side) {
      // Left of the line the baseline is kGap + descent away; right of it, kGap + cap height.
      const double bx = side == 0 ? m.x - kGap - 0.24 * style.px : m.x + kGap + 0.76 * style.px;
      for (int k = 0; k < kHeights; ++k) {
        if (travel < 0.0 && k > 0) break;
        const double y0 = frame.y0 + kInset + std::max(travel, 0.0) * k / (kHeights - 1);
        const Box b = text_box(bx, y0, "end", true, m.text, style);
        if (!b.inside(frame, 0.0)) continue;
        if (std::any_of(placed.begin(), placed.end(),
                        [&](const Box& o) { return o.overlaps(b, 0.0); }))
          continue;
        // Data under the label costs most; then a preference for the top and for the left.
        const double cost = static_cast<double>(occ.count(b)) * 10.0 + k * 2.0 + side;
        if (!found || cost < best_cost) {
          found = true;
          best_cost = cost;
          best = {m.x, bx, y0, m.text, b, true, "end"};
        }
      }
    }
    // Above the frame, horizontal, when every place beside the line has data under it: the
    // strip between the title and the frame (a label on the data is legible only by its halo).
    if (!found || best_cost >= 10.0) {
      for (const char* anchor : {"middle", "start", "end"}) {
        const std::string_view a(anchor);
        const double ax = a == "start" ? m.x - 2.0 : a == "end" ? m.x + 2.0 : m.x;
        const double ay = frame.y0 - 4.0;
        const Box b = text_box(ax, ay, a, false, m.text, style);
        if (b.x0 < above.x0 || b.x1 > above.x1 || b.y0 < above.y0) continue;
        if (std::any_of(placed.begin(), placed.end(),
                        [&](const Box& o) { return o.overlaps(b, 0.0); }))
          continue;
        found = true;
        best = {m.x, ax, ay, m.text, b, false, std::string(a)};
        break;
      }
    }
    if (!found) {
      unplaced.push_back(m.text);
      continue;
    }
    placed.push_back(best.box);
    out.push_back(best);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Decimation

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

// Contiguous runs of one code in a timeline series: [x_start, x_end) per run.
std::vector<std::pair<double, double>> runs_of(const Series& s, double code) {
  std::vector<std::pair<double, double>> out;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  bool in = false;
  double start = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(s.x[i])) continue;
    const bool match = s.y[i] == code;
    if (match && !in) start = s.x[i];
    if (!match && in) out.emplace_back(start, s.x[i]);
    in = match;
  }
  if (in && n > 0) out.emplace_back(start, s.x[n - 1]);
  return out;
}

}  // namespace lathectl::io::detail
