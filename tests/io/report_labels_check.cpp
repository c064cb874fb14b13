// Every plot of every report a run wrote: no two labels overlap and every label (titles, axis
// labels, tick labels, marker labels, legend entries) lies inside its SVG's viewBox.
//
// usage: report_labels_check DIR...   (each DIR/<name>/report.html or lobes.html is checked)
//
// It parses the <text> elements of each <svg class="chart"> as the page has them (x, y,
// text-anchor, transform, class) and computes each one's box with the renderer's own text
// metrics (io::detail::text_box). Limits: widths are ESTIMATES from DejaVu Sans' advance widths
// (report_layout.cpp), not the browser's layout; a label could still touch a line of data (only
// marker labels avoid the data, and only as far as an occupancy grid of 3 px cells sees it); the
// check is for the texts' boxes, not for what is drawn under them. The font sizes it assumes are
// checked against the page's CSS.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "io/report_plot.hpp"

namespace fs = std::filesystem;
using lathectl::io::detail::Box;
using lathectl::io::detail::text_box;
using lathectl::io::detail::text_style;

namespace {

std::string unescape(std::string s) {
  const std::pair<const char*, const char*> entities[] = {
      {"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&#39;", "'"}, {"&amp;", "&"}};
  for (const auto& [from, to] : entities)
    for (auto p = s.find(from); p != std::string::npos; p = s.find(from, p + 1))
      s.replace(p, std::string(from).size(), to);
  return s;
}

std::string attr(const std::string& attrs, const std::string& name) {
  const std::regex re("\\b" + name + "=\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(attrs, m, re) ? m[1].str() : std::string();
}

struct Label {
  Box box;
  std::string cls, text;
};

std::string describe(const Label& l) {
  char b[160];
  std::snprintf(b, sizeof b, " [%.1f,%.1f]–[%.1f,%.1f]", l.box.x0, l.box.y0, l.box.x1, l.box.y1);
  return l.cls + " \"" + l.text + "\"" + b;
}

// Returns the number of problems found in one page.
int check_page(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string html = ss.str();
  int problems = 0;
  // The sizes text_style() assumes are the page's.
  for (const char* rule :
       {"svg.chart text { font-family: inherit; font-size: 12px",
        "svg.chart text.title { font-size: 15px", "svg.chart text.label { font-size: 13px",
        "svg.chart text.nodata { font-size: 16px", "svg.chart .marker text { font-size: 11px"}) {
    if (html.find(rule) == std::string::npos) {
      std::cout << file.string() << ": the CSS no longer says \"" << rule
                << "\" (update text_style in report_layout.cpp)\n";
      ++problems;
    }
  }
  // Found with find(), not std::regex: libstdc++'s regex recurses per character and a report's
  // SVG runs to megabytes.
  const std::regex rot_re("translate\\(([-0-9.]+) ([-0-9.]+)\\) rotate\\(-90\\)");
  std::size_t plots = 0, labels = 0;
  for (std::size_t at = html.find("<svg class=\"chart\""); at != std::string::npos;
       at = html.find("<svg class=\"chart\"", at + 1)) {
    ++plots;
    const std::size_t open_end = html.find('>', at);
    const std::size_t close = html.find("</svg>", at);
    if (open_end == std::string::npos || close == std::string::npos) break;
    const std::string head = html.substr(at, open_end - at);
    double w = 0.0, h = 0.0;
    if (std::sscanf(attr(head, "viewBox").c_str(), "0 0 %lf %lf", &w, &h) != 2) {
      std::cout << file.string() << ": a chart without a viewBox\n";
      ++problems;
      continue;
    }
    const Box view{0.0, 0.0, w, h};
    const std::string title = unescape(attr(head, "aria-label"));
    std::vector<Label> found;
    for (std::size_t t = html.find("<text", open_end); t != std::string::npos && t < close;
         t = html.find("<text", t + 1)) {
      const std::size_t te = html.find('>', t);
      const std::size_t tc = html.find("</text>", te);
      const std::string attrs = html.substr(t + 5, te - t - 5);
      Label l{{}, attr(attrs, "class"), unescape(html.substr(te + 1, tc - te - 1))};
      std::string anchor = attr(attrs, "text-anchor");
      if (anchor.empty()) anchor = "start";
      std::smatch rm;
      const std::string transform = attr(attrs, "transform");
      if (std::regex_search(transform, rm, rot_re)) {
        l.box = text_box(std::stod(rm[1].str()), std::stod(rm[2].str()), anchor, true, l.text,
                         text_style(l.cls));
      } else {
        l.box = text_box(std::stod(attr(attrs, "x")), std::stod(attr(attrs, "y")), anchor, false,
                         l.text, text_style(l.cls));
      }
      found.push_back(l);
    }
    labels += found.size();
    for (std::size_t i = 0; i < found.size(); ++i) {
      if (!found[i].box.inside(view)) {
        std::cout << file.string() << ": \"" << title
                  << "\": outside the viewBox: " << describe(found[i]) << "\n";
        ++problems;
      }
      for (std::size_t j = i + 1; j < found.size(); ++j)
        if (found[i].box.overlaps(found[j].box)) {
          std::cout << file.string() << ": \"" << title << "\": overlap: " << describe(found[i])
                    << " and " << describe(found[j]) << "\n";
          ++problems;
        }
    }
  }
  std::cout << (problems ? "✘ " : "✔ ") << file.string() << ": " << plots << " plots, " << labels
            << " labels\n";
  return problems;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: report_labels_check DIR...\n";
    return 2;
  }
  int problems = 0, pages = 0;
  for (int a = 1; a < argc; ++a) {
    for (const auto& e : fs::directory_iterator(argv[a])) {
      for (const char* name : {"report.html", "lobes.html"}) {
        const fs::path p = e.path() / name;
        if (!fs::is_regular_file(p)) continue;
        ++pages;
        problems += check_page(p);
      }
    }
  }
  if (pages == 0) {
    std::cout << "no report.html or lobes.html under the given directories\n";
    return 1;
  }
  std::cout << pages << " pages, " << problems << " problem(s)\n";
  return problems == 0 ? 0 : 1;
}
