#pragma once
// The tools of a program beyond the scenario's [tool] (`lathectl optimize --tool-file FILE`):
// per T number what the prediction and the feeds need that LinuxCNC's tool table does not say.
//
//   [[tool]]
//   number = 2
//   kind = "grooving"          # turning, facing, boring, grooving, parting, threading
//   insert_width_mm = 3.0      # grooving and parting: the width of cut of a plunge
//   nose_radius_mm = 0.2       # the finish Ra = f²/(32 r); default: the scenario's [tool]
//   feed_min_mm_per_rev = 0.02 # the maker's feed range for the insert
//   feed_max_mm_per_rev = 0.08
//
// A tool listed here is optimised within its own feed range; a grooving or parting tool's cut is
// taken at its insert's width (the width of cut b of the cutting law, the feed per revolution
// its chip thickness), not at the turning nose's engagement; a threading tool's feed moves
// outside threads keep their feeds. Turning, facing and boring tools are predicted with the
// scenario's insert geometry and cutting law (their own nose radius only for the finish).
// Every error names the file, line and key (io::InputError); unknown keys are errors.

#include <string>
#include <vector>

namespace lathectl::optimize {

struct ToolSpec {
  enum class Kind { Turning, Facing, Boring, Grooving, Parting, Threading };
  int number = 0;
  Kind kind = Kind::Turning;
  double insert_width_mm = 0.0;  // grooving, parting
  double nose_radius_mm = 0.0;   // 0: the scenario's
  double feed_min_mm_per_rev = 0.0, feed_max_mm_per_rev = 0.0;  // 0: the scenario's controller
  // A plunge tool: its cut is as wide as its insert.
  [[nodiscard]] bool plunge() const noexcept {
    return kind == Kind::Grooving || kind == Kind::Parting;
  }
};
const char* kind_name(ToolSpec::Kind k) noexcept;

std::vector<ToolSpec> read_tool_file(const std::string& text, const std::string& file);

// The spec of tool `number`, nullptr when the file does not list it.
const ToolSpec* find_tool(const std::vector<ToolSpec>& tools, int number) noexcept;

}  // namespace lathectl::optimize
