#include "lathectl/io/tool_file.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/format.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {

const char* kind_name(ToolSpec::Kind k) noexcept {
  switch (k) {
    case ToolSpec::Kind::Turning: return "turning";
    case ToolSpec::Kind::Facing: return "facing";
    case ToolSpec::Kind::Boring: return "boring";
    case ToolSpec::Kind::Grooving: return "grooving";
    case ToolSpec::Kind::Parting: return "parting";
    case ToolSpec::Kind::Threading: return "threading";
  }
  return "turning";
}

std::vector<ToolSpec> read_tool_file(const std::string& text, const std::string& file) {
  const auto doc = TomlDocument::parse(text, file);
  TableReader root(doc.root(), file, "");
  std::vector<ToolSpec> out;
  const std::vector<std::string> kinds{"turning", "facing",  "boring",
                                       "grooving", "parting", "threading"};
  std::unordered_set<int> seen;  // the duplicate check in linear time (10⁵ tools took minutes)
  for (auto& r : root.tables("tool")) {
    ToolSpec t;
    t.number = static_cast<int>(r.integer("number", 0, 99999));
    if (!seen.insert(t.number).second)
      r.fail("number", "tool " + std::to_string(t.number) + " twice");
    const std::string k = r.choice("kind", kinds);
    for (std::size_t i = 0; i < kinds.size(); ++i)
      if (kinds[i] == k) t.kind = static_cast<ToolSpec::Kind>(i);
    r.read(Param{"insert_width_mm", Range::closed(0.1, 50.0),
                 "width of a grooving or parting insert: a plunge's width of cut"},
           t.insert_width_mm);
    r.check(!t.plunge() || t.insert_width_mm > 0.0, "insert_width_mm",
            "required for a " + k + " tool (the width of cut of its plunge)");
    r.read(Param{"nose_radius_mm", Range::closed(0.01, 10.0), "corner radius (the finish)"},
           t.nose_radius_mm);
    r.read(Param{"feed_min_mm_per_rev", Range::positive(), "the insert's least feed"},
           t.feed_min_mm_per_rev);
    r.read(Param{"feed_max_mm_per_rev", Range::closed(1e-3, 10.0), "the insert's largest feed"},
           t.feed_max_mm_per_rev);
    r.check(t.feed_min_mm_per_rev == 0.0 || t.feed_max_mm_per_rev == 0.0 ||
                t.feed_min_mm_per_rev < t.feed_max_mm_per_rev,
            "feed_max_mm_per_rev", "feed_min_mm_per_rev < feed_max_mm_per_rev");
    r.finish();
    out.push_back(t);
  }
  root.finish();
  return out;
}

std::vector<TableTool> read_tool_table(const std::string& text, const std::string& file) {
  std::vector<TableTool> out;
  std::unordered_map<int, int> first_line;  // tool number → its line: linear, not quadratic
  std::istringstream in(text);
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line.front() == ';') continue;
    const std::string words = line.substr(0, line.find(';'));
    std::istringstream ws(words);
    TableTool t;
    t.line = line_no;
    bool has_t = false, any = false;
    for (std::string w; ws >> w;) {
      any = true;
      auto bad = [&](const std::string& why) {
        throw InputError(located(file, line_no, 0,
                                         "tool table word '" + printable(w) + "': " + why +
                                             " (LinuxCNC skips the line: the tool is missing)"));
      };
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(w[0])));
      const std::string value = w.substr(1);
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(value.c_str(), &end);
      if (value.empty() || end != value.c_str() + value.size() || errno != 0 || !std::isfinite(v))
        bad("not a number after the letter");
      const bool integral = v == std::floor(v) && std::abs(v) < 1e9;
      switch (letter) {
        case 'T':
          if (!integral || v < 0) bad("a tool number is a whole number ≥ 0");
          t.number = static_cast<int>(v);
          has_t = true;
          break;
        case 'P':
          if (!integral) bad("a pocket is a whole number");
          break;
        case 'D':
          if (v < 0.0) bad("a diameter is ≥ 0");
          t.diameter_mm = v;
          break;
        case 'I': t.front_angle_deg = v; break;
        case 'J': t.back_angle_deg = v; break;
        case 'Q':
          if (!integral || v < 0 || v > 9) bad("the orientation is a whole number 0–9");
          t.orientation = static_cast<int>(v);
          break;
        case 'X': case 'Y': case 'Z': case 'A': case 'B': case 'C': case 'U': case 'V': case 'W':
          break;  // offsets: rs274 applies them
        default: bad("not a tool table word (T P D X Y Z A B C U V W I J Q)");
      }
    }
    if (!any) continue;
    if (!has_t)
      throw InputError(located(file, line_no, 0, "a tool table line without its T word"));
    if (const auto [at, fresh] = first_line.emplace(t.number, line_no); !fresh)
      throw InputError(located(file, line_no, 0,
                                       "tool " + std::to_string(t.number) + " again (first on line " +
                                           std::to_string(at->second) + ")"));
    out.push_back(t);
  }
  return out;
}

void apply_tool_table(std::vector<ToolSpec>& specs, const std::vector<TableTool>& table,
                      const std::string& tool_file, const std::string& table_file) {
  std::unordered_map<int, const TableTool*> by_number;
  for (const auto& x : table) by_number[x.number] = &x;  // the last, as before (numbers unique)
  for (auto& s : specs) {
    const auto found = by_number.find(s.number);
    if (found == by_number.end()) continue;
    const TableTool* t = found->second;
    if (t->diameter_mm > 0.0) {
      const double r = 0.5 * t->diameter_mm;
      if (s.nose_radius_mm > 0.0 && std::abs(s.nose_radius_mm - r) > 1e-3)
        throw InputError(located(
            tool_file, 0, 0,
            "tool " + std::to_string(s.number) + ": nose_radius_mm = " + fmt(s.nose_radius_mm) +
                " mm, but LinuxCNC's tool table " + table_file + ":" + std::to_string(t->line) +
                " gives D" + fmt(t->diameter_mm) + " (a nose radius of " + fmt(r) +
                " mm): one of the two is wrong"));
      s.nose_radius_mm = r;
    }
    s.front_angle_deg = t->front_angle_deg;
    s.back_angle_deg = t->back_angle_deg;
    s.orientation = t->orientation;
  }
}

const ToolSpec* find_tool(const std::vector<ToolSpec>& tools, int number) noexcept {
  for (const auto& t : tools)
    if (t.number == number) return &t;
  return nullptr;
}

ToolGeometry tool_geometry(const std::vector<ToolSpec>& specs,
                           const std::vector<TableTool>& table, int number,
                           const ToolGeometry& scenario) noexcept {
  ToolGeometry g = scenario;
  for (const auto& t : table) {  // the last of a number, as apply_tool_table (numbers unique)
    if (t.number != number) continue;
    // Q0 with a nose (D > 0): its centre. Q0 without one: LinuxCNC's point tool, the point
    // where the program puts it, on a nose the table does not give: the scenario's tip.
    if (t.orientation != 0 || t.diameter_mm > 0.0) g.orientation = t.orientation;
    g.nose_radius_mm = t.diameter_mm > 0.0 ? 0.5 * t.diameter_mm : scenario.nose_radius_mm;
    // I and J where the table gives either (both 0: not given), else the scenario's.
    const bool angles = t.front_angle_deg != 0.0 || t.back_angle_deg != 0.0;
    g.front_angle_deg = angles ? t.front_angle_deg : scenario.front_angle_deg;
    g.back_angle_deg = angles ? t.back_angle_deg : scenario.back_angle_deg;
  }
  if (const ToolSpec* s = find_tool(specs, number); s != nullptr && s->nose_radius_mm > 0.0)
    g.nose_radius_mm = s->nose_radius_mm;
  return g;
}

double largest_nose_radius_mm(const std::vector<ToolSpec>& specs,
                              const std::vector<TableTool>& table, double scenario_mm) noexcept {
  double r = scenario_mm;
  for (const auto& t : table) r = std::max(r, 0.5 * t.diameter_mm);
  for (const auto& s : specs) r = std::max(r, s.nose_radius_mm);
  return r;
}

}  // namespace lathectl::io
