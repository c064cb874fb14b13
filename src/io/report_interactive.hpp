#pragma once
// Internal to the report: the interactive plots (report_interactive.cpp), beside the static SVG
// plots (report_plot.cpp) that stay as the fallback without scripts and for printing.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/io/report.hpp"

namespace lathectl::io::detail {

// A plot over time (its x label starts with "time"): it gets an interactive chart.
bool time_axis(const Plot& plot);
bool has_interactive_plots(const std::vector<Plot>& plots);

// Appends, for the time-axis plots (each in <div class="plot-box" id="plot-N">), their data as
// min/max pyramids, the uPlot library and the page script; nothing when there is no such plot.
// The pyramids' finest levels are capped so the data stay under budget_bytes.
void render_interactive(std::string& out, const std::vector<Plot>& plots,
                        std::size_t budget_bytes);

// The page's styles for the interactive plots and for printing (the static SVG prints).
extern const std::string_view kInteractiveStyle;

}  // namespace lathectl::io::detail
