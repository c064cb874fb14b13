#include "lathectl/io/report.hpp"

#include "lathectl/io/output.hpp"

#include "report_interactive.hpp"
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

namespace lathectl::io {
namespace {

using detail::escape;
using detail::render_plot;

// ---------------------------------------------------------------------------------------------
// Text and number formatting


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
th.num, td.num { text-align: right; }
td.num { white-space: nowrap; }  /* headers wrap; a table still too wide scrolls in its card */
@media (min-width: 1360px) { main { max-width: 1240px; } }
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
  out += kGeneratorMeta;
  out += "\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + escape(title) + "</title>\n<style>";
  out += kStyle;
  out += detail::kInteractiveStyle;
  out += "</style>\n</head>\n<body>\n<main>\n";
}

// The interactive plots' data (min/max pyramids, base64) in one report: keeps report.html under
// 10 MB with room for the page, the SVG fallback and uPlot (about 50 kB).
constexpr std::size_t kPlotDataBudget = 8'000'000;

// Where the documentation lives: docs/ in the sources, this directory once installed.
constexpr std::string_view kInstalledDocs = "/usr/share/doc/lathectl/docs/";

void end_page(std::string& out, std::string_view doc_page, bool scripts = false) {
  const std::string page = doc_page.empty() ? std::string("README.md") : std::string(doc_page);
  out += scripts ? "<footer>Generated by lathectl. Self-contained page, no network: the plots over "
                   "time are uPlot charts (inlined, MIT licence); without scripts, and in print, "
                   "the static plots show.<br>\n"
                 : "<footer>Generated by lathectl. Self-contained page: no scripts, no network.<br>\n";
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

// The table alone (no section, no title).
void table_html(std::string& out, const Table& table) {
  const std::vector<bool> numeric = numeric_columns(table);
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
  out += "</tbody></table></div>\n";
}

void render_table(std::string& out, const Table& table) {
  out += "<section class=\"table\">\n";
  if (!table.title.empty()) out += "<h2>" + escape(table.title) + "</h2>\n";
  table_html(out, table);
  out += "</section>\n";
}

}  // namespace

std::string render_html(const Report& report, std::size_t max_points) {
  std::string out;
  out.reserve(64 * 1024);
  begin_page(out, report.title);

  out += "<header>\n<h1>" + escape(report.title) + "</h1>\n";
  if (!report.subtitle.empty())
    out += "<p class=\"subtitle\">" + escape(report.subtitle) + "</p>\n";
  if (!report.links.empty()) {
    out += "<nav class=\"links\">";
    for (std::size_t i = 0; i < report.links.size(); ++i)
      out += (i ? " · " : "") + std::string("<a href=\"") + escape(report.links[i].href) + "\">" +
             escape(report.links[i].text) + "</a>";
    out += "</nav>\n";
  }
  out += "</header>\n";

  const std::vector<std::string> paras = paragraphs(report.description);
  if (!paras.empty()) {
    out += "<section class=\"description\">\n";
    for (const std::string& p : paras) out += "<p>" + escape(p) + "</p>\n";
    out += "</section>\n";
  }

  if (!report.verdict.empty()) {
    out += std::string("<section class=\"verdict ") + (report.verdict_ok ? "ok" : "bad") +
           "\" id=\"verdict\">\n<h2>" +
           escape(report.verdict_table.title.empty() ? std::string("Verdict")
                                                     : report.verdict_table.title) +
           "</h2>\n<p class=\"mark\">" + escape(report.verdict) + "</p>\n";
    if (!report.verdict_table.rows.empty()) table_html(out, report.verdict_table);
    link_list(out, report.verdict_items, "notes");
    out += "</section>\n";
  }
  if (!report.model_checks.empty()) {
    out += std::string("<section class=\"model-checks ") + (report.model_checks_ok ? "ok" : "bad") +
           "\" id=\"model-checks\">\n<h2>Model checks: the seed's claims</h2>\n<p>" +
           escape(report.model_checks) + "</p>\n";
    link_list(out, report.model_check_items, "notes");
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

  const auto plots = [&] {
    if (report.plots.empty() && report.heat_maps.empty()) return;
    out += "<section class=\"plots\" id=\"plots\">\n<h2>Plots</h2>\n";
    for (std::size_t i = 0; i < report.plots.size(); ++i) {
      out += "<div class=\"plot-box\" id=\"plot-" + std::to_string(i) + "\">\n";
      render_plot(out, report.plots[i], i, max_points);
      out += "</div>\n";
    }
    for (const HeatMap& m : report.heat_maps) {
      out += "<div class=\"plot-box\">\n";
      detail::render_heat_map(out, m);
      out += "</div>\n";
    }
    out += "</section>\n";
  };
  if (report.plots_first) plots();
  for (const Table& t : report.tables) render_table(out, t);
  if (!report.plots_first) plots();
  detail::render_interactive(out, report.plots, kPlotDataBudget);

  end_page(out, report.doc_page, detail::has_interactive_plots(report.plots));
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
