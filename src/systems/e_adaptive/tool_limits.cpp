#include "systems/e_adaptive/tool_limits.hpp"

#include <unordered_set>

#include "lathectl/io/toml_reader.hpp"

namespace lathectl::systems::e_adaptive {

ToolTable read_tool_table(const std::string& text, const std::string& file) {
  using io::Param;
  using io::Range;
  const auto doc = io::TomlDocument::parse(text, file);
  io::TableReader root(doc.root(), file, "");
  ToolTable t;
  if (auto m = root.table("machine")) {
    m->read(Param{"limit_max", Range::positive(), "rating in the sensor's unit"}, t.limit_max);
    m->read(Param{"feed_max_mm_per_rev", Range::positive(), "largest feed bound"},
            t.feed_max_mm_per_rev);
    m->finish();
  }
  std::unordered_set<int> seen;  // the duplicate check in linear time (10⁵ tools took minutes)
  for (auto& r : root.tables("tool")) {
    control::ToolLimits l;
    l.number = static_cast<int>(r.integer("number", 0, 99999));
    if (!seen.insert(l.number).second)
      r.fail("number", "tool " + std::to_string(l.number) + " twice");
    r.read(Param{"limit", Range::positive(), "limit (N or W)"}, l.limit);
    r.read(Param{"feed_min_mm_per_rev", Range::positive(), "feed lower bound"},
           l.feed_min_mm_per_rev);
    r.read(Param{"feed_max_mm_per_rev", Range::positive(), "feed upper bound"},
           l.feed_max_mm_per_rev);
    r.check(l.feed_min_mm_per_rev == 0.0 || l.feed_max_mm_per_rev == 0.0 ||
                l.feed_min_mm_per_rev < l.feed_max_mm_per_rev,
            "feed_max_mm_per_rev", "feed_min_mm_per_rev < feed_max_mm_per_rev");
    r.check(t.limit_max == 0.0 || l.limit <= t.limit_max, "limit",
            "above the machine's limit_max");
    r.check(t.feed_max_mm_per_rev == 0.0 || l.feed_max_mm_per_rev <= t.feed_max_mm_per_rev,
            "feed_max_mm_per_rev", "above the machine's feed_max_mm_per_rev");
    l.adaptive = r.boolean("adaptive", true);
    r.read(Param{"reference_pct", Range{0.0, 200.0, true, false}, "% of the taught load"},
           l.reference_pct);
    r.read(Param{"warn_pct", Range::closed(0.0, 1000.0), "warning level, % of the reference"},
           l.warn_pct);
    r.read(Param{"hold_pct", Range::closed(0.0, 1000.0), "feed-hold level, % of the reference"},
           l.hold_pct);
    r.check(l.hold_pct == 0.0 || l.warn_pct == 0.0 || l.warn_pct < l.hold_pct, "hold_pct",
            "warn_pct < hold_pct");
    r.finish();
    t.tools.push_back(l);
  }
  root.finish();
  return t;
}

std::vector<Taught> read_taught(const std::string& text, const std::string& file) {
  const auto doc = io::TomlDocument::parse(text, file);
  io::TableReader root(doc.root(), file, "");
  std::vector<Taught> out;
  for (auto& r : root.tables("taught")) {
    Taught t;
    t.tool = static_cast<int>(r.integer("tool", 0, 99999));
    t.operation = static_cast<int>(r.integer("operation", 0, 99999, 0));
    t.reference = r.number("reference", io::Range::positive());
    t.unit = r.choice("unit", {"N", "W"});
    r.finish();
    out.push_back(t);
  }
  root.finish();
  return out;
}

}  // namespace lathectl::systems::e_adaptive
