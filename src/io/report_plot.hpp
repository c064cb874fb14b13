#pragma once
// Internal to the report: the SVG plot renderer (report_plot.cpp), its numbers and scales
// (report_scale.cpp), its text metrics and label placement (report_layout.cpp), and HTML
// escaping, shared by the page (report.cpp) and by the layout test
// (tests/io/report_layout_test.cpp).

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lathectl/io/report.hpp"

namespace lathectl::io::detail {

std::string escape(std::string_view s);

// ---------------------------------------------------------------------------------------------
// Text metrics. Every <text> of a plot carries one of these classes; its size is the page's CSS
// (svg.chart text …, report.cpp). Widths are ESTIMATES from the advance widths of DejaVu Sans (the
// system-ui/sans-serif fallback on Debian; wider than Segoe UI, Roboto and Helvetica, so an
// estimate that fits here fits there): ASCII from the font's table, other characters at a
// conservative 0.70 em (letters below U+2000: µ, ω, δ …) or 0.84 em (symbols: −, ×, ≈ …).
struct TextStyle {
  double px = 12.0;
  bool bold = false;
};
TextStyle text_style(std::string_view cls);  // "title", "label", "tick", "legend", "mark", "nodata"
double text_width(std::string_view s, const TextStyle& style);

struct Box {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  // True when the two boxes share more than `slack` px in both directions.
  bool overlaps(const Box& o, double slack = 0.5) const;
  bool inside(const Box& o, double slack = 0.5) const;
};

// The ink box of a text element: at (x, y) (the baseline), text-anchor start|middle|end, and
// either horizontal or rotated by −90° about (x, y) (reading upwards). Vertical extent: cap
// height 0.76 em above the baseline, descenders 0.24 em below.
Box text_box(double x, double y, std::string_view anchor, bool rotated, std::string_view text,
             const TextStyle& style);

// A label the layout placed (for tests and for the caller's own checks).
struct PlacedText {
  Box box;
  std::string cls;
  std::string text;
};

// ---------------------------------------------------------------------------------------------
// Marker labels: placed beside their dashed line, on whichever side and height keeps them off
// the other labels and off the data (an occupancy grid of the plot area).
class Occupancy {
 public:
  Occupancy(double left, double top, double width, double height);
  void mark_point(double x, double y);
  void mark_line(double x0, double y0, double x1, double y1);
  void mark_rect(double x0, double y0, double x1, double y1);
  std::size_t count(const Box& b) const;  // occupied cells under the box

 private:
  static constexpr double kCell = 3.0;
  double left_, top_;
  std::size_t nx_, ny_;
  std::vector<unsigned char> cells_;
};

struct MarkerLabel {
  double x = 0.0;  // the marker line's pixel column
  std::string text;
};
struct PlacedMarkerLabel {
  double line_x = 0.0;      // the marker line's pixel column
  double x = 0.0, y = 0.0;  // the text's origin (translate() when rotated)
  std::string text;
  Box box;
  bool rotated = true;  // beside the line, reading upwards; false: above the frame
  std::string anchor = "end";
};
// Places each label rotated beside its line inside the frame, avoiding `placed` (extended with
// the new boxes) and the occupied cells; where every such place has data under it, horizontally
// in the strip `above` the frame if there is room. A label with the same
// text as one already placed within 40 px is left out (its line is named by the other); a label
// that fits nowhere is returned in `unplaced`.
std::vector<PlacedMarkerLabel> place_marker_labels(const std::vector<MarkerLabel>& labels,
                                                   const Box& frame, const Box& above,
                                                   const Occupancy& occ, std::vector<Box>& placed,
                                                   std::vector<std::string>& unplaced);

// ---------------------------------------------------------------------------------------------
// Numbers and axis scales (report_scale.cpp).
// Locale-independent (std::to_chars), unlike printf, so a program that calls setlocale() cannot
// turn the decimal point of an SVG coordinate into a comma.
std::string fixed(double v, int decimals);
std::string general(double v, int precision);  // %g-like with a compact exponent: 1.5e6, 2e-5
std::string coord(double v);  // one SVG coordinate, 0.1 px resolution, no trailing ".0", no "-0"
// Tick label for v on an axis [lo, hi] with the given (1-2-5) step.
std::string tick_label(double v, double step, double lo, double hi);
double nice_step(double raw);  // the nearest 1-2-5 step
struct Ticks {
  std::vector<double> values;
  double step = 1.0;
};
Ticks make_ticks(double lo, double hi, double target_count);
struct Range {
  double lo = 0.0;
  double hi = 1.0;
};
// Widens a degenerate range; pads a proper one by `pad_fraction` of its span on each side.
Range widen(double lo, double hi, double pad_fraction);
// Decade ticks on a log10 axis [lo, hi] (in decades), and their labels.
Ticks log_ticks(double lo, double hi);
std::string log_tick_label(double decades);

// ---------------------------------------------------------------------------------------------
// Data: runs of finite points, decimated; runs of one code in a timeline series.
using Point = std::pair<double, double>;
using Segment = std::vector<Point>;  // a run of finite points, drawn as one polyline
bool finite_point(const Series& s, std::size_t i);
// Splits the series into runs of finite points. If it has more than max_points finite points,
// each of max_points/2 index buckets contributes only its minimum and maximum (in index order),
// so spikes survive decimation.
std::vector<Segment> segments_of(const Series& s, std::size_t max_points);
// Contiguous runs of one code in a timeline series: [x_start, x_end) per run.
std::vector<std::pair<double, double>> runs_of(const Series& s, double code);

// The colour a series is drawn in: its own, else the palette's by its index in the plot.
std::string series_color(const Series& s, std::size_t index);
// One <figure> with an inline SVG plot; series longer than max_points decimated by min/max per
// pixel column. `placed` (optional) receives the box of every text the layout wrote.
void render_plot(std::string& out, const Plot& plot, std::size_t plot_index, std::size_t max_points,
                 std::vector<PlacedText>* placed = nullptr);

// One <figure> with an inline SVG heat map (report_heatmap.cpp).
void render_heat_map(std::string& out, const HeatMap& map);

}  // namespace lathectl::io::detail
