#pragma once
// HTML report: a self-contained page (inline CSS, SVG and scripts, no network) that opens offline
// in any browser. Every plot is drawn here, in C++, as an SVG polyline; where the browser runs
// scripts, the interactive plots (zoom, pan, read-out: io/report_interactive.cpp, with the uPlot
// library inlined) take its place, and without scripts the SVG stays. Nothing installed is needed
// to read it.

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/sim/plot_pyramid.hpp"

namespace lathectl::io {

struct Series {
  std::string name;       // legend text
  std::vector<double> x;  // same length as y
  std::vector<double> y;
  std::string color;    // CSS colour; empty → from a default palette
  bool dashed = false;  // dashed line (e.g. setpoints, formula curves)
  bool points = false;  // draw markers instead of a line (e.g. measured points)
  // The whole record's min/max pyramid when x/y are already decimated from it (a streamed
  // recorder): the interactive plot zooms into it (levels over the report's budget left out);
  // null: the interactive plot builds one from x/y.
  std::shared_ptr<const sim::PlotPyramid> pyramid = {};
};

struct Marker {  // vertical line on a time axis: an event, alarm or disturbance
  double x = 0.0;
  std::string label;
};

struct Plot {
  std::string title;
  std::string x_label;  // with unit, e.g. "time [s]"
  std::string y_label;  // with unit
  std::vector<Series> series;
  std::vector<Marker> markers;
  // Optional layout (the defaults give a linear plot fitted to the data):
  bool log_y = false;  // logarithmic y axis (values <= 0 are left out)
  // Fixed axis ranges (NaN: from the data). A fixed x range lines stacked plots up and shows a
  // gap at the end of a run as a gap; data beyond a fixed y range is clipped at the frame.
  double x_min = std::numeric_limits<double>::quiet_NaN();
  double x_max = std::numeric_limits<double>::quiet_NaN();
  double y_min = std::numeric_limits<double>::quiet_NaN();
  double y_max = std::numeric_limits<double>::quiet_NaN();
  // Timeline band: when not empty, each series' y values are codes and the plot has one lane
  // per listed code (value, name), filled where the series holds that code (e.g. reason codes).
  std::vector<std::pair<double, std::string>> lanes = {};
};

// A heat map: z[iy][ix] over the grid xs × ys (category labels, in order), coloured from the
// lowest z (blue) to the highest (red); a NaN cell is grey (no value: a failed case). Each cell
// shows its value in a tooltip.
// Lines over a heat map (a boundary drawn across the cells), in the numbers the cells stand for.
struct HeatMapLine {
  std::string name;       // the caption's legend
  std::vector<double> x;  // same length as y; a NaN breaks the line
  std::vector<double> y;
  std::string color = "#000";
  bool dashed = false;
  bool points = false;  // markers instead of a line
};

struct HeatMap {
  std::string title;
  std::string x_label;  // with unit
  std::string y_label;
  std::string z_label;  // the colour's quantity, with unit
  std::vector<std::string> xs;
  std::vector<std::string> ys;
  std::vector<std::vector<double>> z;  // ys.size() rows of xs.size()
  // Optional lines over the cells: the numbers the columns and rows stand for (strictly
  // increasing, one per xs / ys entry: a cell's centre), placed linearly between the centres
  // (and beyond the outer ones with their spacing), clipped to the map. Without both, no lines.
  std::vector<double> x_values = {}, y_values = {};
  std::vector<HeatMapLine> lines = {};
  // The colour scale: logarithmic (values ≤ 0 grey), and white at z_centre when it is finite
  // (below it blue, above it red: a threshold), else at the middle of the values' span.
  bool log_z = false;
  double z_centre = std::numeric_limits<double>::quiet_NaN();
};

struct Table {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

// A line of text that links somewhere (href empty: plain text).
struct Link {
  std::string text;
  std::string href;
};

struct Report {
  std::string title;
  std::string subtitle;     // scenario file, system
  std::string description;  // free text (paragraphs separated by blank lines)
  std::vector<std::pair<std::string, std::string>> metrics;  // name → formatted value
  std::vector<std::string> notes;                            // findings, each a short paragraph
  // Parallel to notes (may be shorter): an id for the note's <li>, e.g. "claim-3", "" for none.
  std::vector<std::string> note_ids;
  // The run's verdict, shown first: a headline ("✔ 3 of 3 acceptance criteria met" / "✘ …"),
  // the criteria as a table (criterion, value, limit, ✔/✘; empty: none) and what went wrong,
  // each item linking to its note when it has one. Empty headline: no section.
  std::string verdict;
  bool verdict_ok = true;
  std::vector<Link> verdict_items;
  Table verdict_table = {};
  // The model checks (the seed's claims: does the model reproduce the document?), shown after
  // the verdict and apart from it: a headline and the unmet ones, each linking to its note
  // (href "#claim-3"). Empty headline: no section.
  std::string model_checks = {};
  bool model_checks_ok = true;
  std::vector<Link> model_check_items = {};
  std::vector<Table> tables;
  std::vector<Plot> plots;
  std::vector<HeatMap> heat_maps = {};  // after the plots
  // Page of docs/ that explains the seed, formula and block numbers the report cites (e.g.
  // "system-d-gauging.md"); the footer names it, in the sources and installed. Empty: the index.
  std::string doc_page;
  // Links shown under the title (e.g. back to the index, the run's channels.csv and
  // summary.json); empty: none.
  std::vector<Link> links = {};
  bool plots_first = false;  // plots before the tables (a chart above a long table)
};

// Renders the report as one HTML document. Series longer than max_points are decimated by
// min/max per pixel column so peaks survive.
std::string render_html(const Report& report, std::size_t max_points = 2000);

struct IndexEntry {
  std::string title;
  std::string href;     // relative link to the report
  std::string summary;  // one line: the key numbers
  // Verdict: 0 none shown, 1 all claims met and no alarm (✔), -1 something went wrong (✘).
  int status = 0;
  std::string verdict;  // "✘ 2 of 5 claims not met · alarm …"
  std::vector<Link> problems;  // href e.g. "a/report.html#claim-3"
};
std::string render_index_html(const std::string& title, const std::vector<IndexEntry>& entries);

}  // namespace lathectl::io
