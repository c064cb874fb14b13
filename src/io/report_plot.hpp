#pragma once
// Internal to the report: the SVG plot renderer (report_plot.cpp) and HTML escaping, shared by
// the page (report.cpp).

#include <cstddef>
#include <string>
#include <string_view>

#include "lathectl/io/report.hpp"

namespace lathectl::io::detail {

std::string escape(std::string_view s);
// The colour a series is drawn in: its own, else the palette's by its index in the plot.
std::string series_color(const Series& s, std::size_t index);
// One <figure> with an inline SVG plot; series longer than max_points decimated by min/max per
// pixel column.
void render_plot(std::string& out, const Plot& plot, std::size_t plot_index,
                 std::size_t max_points);

}  // namespace lathectl::io::detail
