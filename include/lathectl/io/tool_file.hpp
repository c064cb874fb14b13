#pragma once
// The tools of a program beyond the scenario's [tool] (`lathectl optimize --tool-file FILE`, the
// same file `linuxcnc-sim --tool-file` gives the LinuxCNC plant, lathectl_plant tool_file=): per T
// number what the prediction, the plant and the feeds need that LinuxCNC's tool table does not
// say. One reader for both (here, in the scenario layer a HAL component links).
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

namespace lathectl::io {

struct ToolSpec {
  enum class Kind { Turning, Facing, Boring, Grooving, Parting, Threading };
  int number = 0;
  Kind kind = Kind::Turning;
  double insert_width_mm = 0.0;  // grooving, parting
  double nose_radius_mm = 0.0;   // 0: the scenario's
  double feed_min_mm_per_rev = 0.0, feed_max_mm_per_rev = 0.0;  // 0: the scenario's controller
  // From LinuxCNC's tool table (read_tool_table): the insert's front and back angle (I, J) [°]
  // and orientation (Q, 1–9; 0: not given).
  double front_angle_deg = 0.0, back_angle_deg = 0.0;
  int orientation = 0;
  // A plunge tool: its cut is as wide as its insert.
  [[nodiscard]] bool plunge() const noexcept {
    return kind == Kind::Grooving || kind == Kind::Parting;
  }
};
const char* kind_name(ToolSpec::Kind k) noexcept;

std::vector<ToolSpec> read_tool_file(const std::string& text, const std::string& file);

// A tool of LinuxCNC's tool table (the INI's [EMCIO]TOOL_TABLE, format of LinuxCNC's
// tooldata_read_entry: per line `T<n> P<n> [D X Y Z A B C U V W I J Q words] [; comment]`, a
// line starting with ';' a comment). On a lathe D is the nose's diameter, I and J the insert's
// front and back angle [°], Q the orientation (1–9) of the tool tip.
struct TableTool {
  int number = 0;
  int line = 0;  // in the table file
  double diameter_mm = 0.0, front_angle_deg = 0.0, back_angle_deg = 0.0;
  int orientation = 0;
};
// Throws io::InputError naming the file, line and word of a line LinuxCNC would skip as
// unrecognised (its tool would then be missing) or a tool listed twice.
std::vector<TableTool> read_tool_table(const std::string& text, const std::string& file);
// The tool table fills what the tool file leaves out: each listed tool's nose radius from D/2
// (D > 0) where the tool file gives none, and its angles and orientation. A tool file's nose
// radius that differs from the table's D/2 by more than 1 µm is an io::InputError naming both
// files and lines.
void apply_tool_table(std::vector<ToolSpec>& specs, const std::vector<TableTool>& table,
                      const std::string& tool_file, const std::string& table_file);

// The spec of tool `number`, nullptr when the file does not list it.
const ToolSpec* find_tool(const std::vector<ToolSpec>& tools, int number) noexcept;

}  // namespace lathectl::io
