#pragma once
// System E's two shop files besides the scenario (lathectl_adaptive reads them at load, never
// in the servo thread; `lathectl check` validates them):
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

#include <string>
#include <vector>

#include "lathectl/control/operation_control.hpp"

namespace lathectl::systems::e_adaptive {

struct ToolTable {
  double limit_max = 0.0;  // 0: not given (the caller's default)
  double feed_max_mm_per_rev = 0.0;
  std::vector<control::ToolLimits> tools;
};

struct Taught {
  int tool = 0;
  int operation = 0;
  double reference = 0.0;
  std::string unit;
};

// Throw io::InputError naming the file, line and key.
ToolTable read_tool_table(const std::string& text, const std::string& file);
std::vector<Taught> read_taught(const std::string& text, const std::string& file);

}  // namespace lathectl::systems::e_adaptive
