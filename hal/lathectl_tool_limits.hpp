#pragma once
// lathectl_adaptive's two files besides the scenario (read at load, never in the servo thread):
//
//   tools=PATH    the per-tool limits table (AFC keeps these in the tool table): the machine's
//                 rating and, per tool number (iocontrol.0.tool-number), the defaults a program
//                 that sets nothing runs with, and the overload levels as percentages:
//
//                   [machine]
//                   limit_max = 5000.0             # rating, in the sensor's unit (N or W)
//                   feed_max_mm_per_rev = 1.0      # no feed bound may exceed it
//                   [[tool]]
//                   number = 1
//                   limit = 1600.0                 # N (force sensor) or W (power sensor)
//                   feed_min_mm_per_rev = 0.05
//                   feed_max_mm_per_rev = 0.6
//                   adaptive = true                # on when the program does not say (E3 = 0)
//                   reference_pct = 100.0          # E3 = 4 with E0 = 0: this % of the taught load
//                   warn_pct = 120.0               # of the reference: operator warning
//                   hold_pct = 150.0               # feed hold (alarm, reset with M64/M65 P0)
//
//   taught=PATH   the teach-in references, written by lathectl_oplog (atomically: a temporary
//                 file renamed over it); absent means nothing taught yet:
//
//                   [[taught]]
//                   tool = 1
//                   operation = 2
//                   reference = 1432.7
//                   unit = "N"
//
// Every error names the file, line and key (io::InputError); unknown keys are errors.

#include <cstdint>
#include <string>
#include <vector>

#include "lathectl/io/toml_reader.hpp"

namespace lathectl::hal {

struct ToolLimits {
  int number = 0;
  double limit = 0.0;  // 0: the scenario's
  double feed_min_mm_per_rev = 0.0;
  double feed_max_mm_per_rev = 0.0;
  bool adaptive = true;
  double reference_pct = 100.0;
  double warn_pct = 0.0;  // 0: off
  double hold_pct = 0.0;
};

struct ToolTable {
  double limit_max = 0.0;  // 0: not given (the caller's default)
  double feed_max_mm_per_rev = 0.0;
  std::vector<ToolLimits> tools;
};

struct Taught {
  int tool = 0;
  int operation = 0;
  double reference = 0.0;
  std::string unit;
};

inline ToolTable read_tool_table(const std::string& text, const std::string& file) {
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
  for (auto& r : root.tables("tool")) {
    ToolLimits l;
    l.number = static_cast<int>(r.integer("number", 0, 99999));
    for (const auto& o : t.tools)
      r.check(o.number != l.number, "number", "tool " + std::to_string(l.number) + " twice");
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

inline std::vector<Taught> read_taught(const std::string& text, const std::string& file) {
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

}  // namespace lathectl::hal
