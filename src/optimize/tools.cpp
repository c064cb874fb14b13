#include "optimize/tools.hpp"

#include "lathectl/io/toml_reader.hpp"

namespace lathectl::optimize {

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
  using io::Param;
  using io::Range;
  const auto doc = io::TomlDocument::parse(text, file);
  io::TableReader root(doc.root(), file, "");
  std::vector<ToolSpec> out;
  const std::vector<std::string> kinds{"turning", "facing",  "boring",
                                       "grooving", "parting", "threading"};
  for (auto& r : root.tables("tool")) {
    ToolSpec t;
    t.number = static_cast<int>(r.integer("number", 0, 99999));
    for (const auto& o : out)
      r.check(o.number != t.number, "number", "tool " + std::to_string(t.number) + " twice");
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

const ToolSpec* find_tool(const std::vector<ToolSpec>& tools, int number) noexcept {
  for (const auto& t : tools)
    if (t.number == number) return &t;
  return nullptr;
}

}  // namespace lathectl::optimize
