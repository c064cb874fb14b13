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
//   nose_radius_mm = 0.2       # the nose (cut, finish Ra = f²/(32 r)); default: table D/2
//   feed_min_mm_per_rev = 0.02 # the maker's feed range for the insert
//   feed_max_mm_per_rev = 0.08
//
// A tool listed here is optimised within its own feed range; a grooving or parting tool's cut is
// taken at its insert's width (the width of cut b of the cutting law, the feed per revolution
// its chip thickness), not at the turning nose's engagement; a threading tool's feed moves
// outside threads keep their feeds. Every tool cuts with its own nose (tool_geometry: this
// nose_radius_mm, else the tool table's D/2, else the scenario's) and the scenario's cutting law.
// Every error names the file, line and key (io::InputError); unknown keys are errors.

#include <string>
#include <vector>

namespace lathectl::io {

struct ToolSpec {
  enum class Kind { Turning, Facing, Boring, Grooving, Parting, Threading };
  int number = 0;
  Kind kind = Kind::Turning;
  double insert_width_mm = 0.0;  // grooving, parting
  double nose_radius_mm = 0.0;   // 0: the tool table's D/2, else the scenario's
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

// The nose tool `number` cuts with, as the plant's geometry (cutting::LathePlant::set_tool): the
// one choice the optimiser's prediction and the LinuxCNC plant (lathectl_plant tool_table=) make.
//   nose radius: the tool file's nose_radius_mm, else the tool table's D/2 (D > 0; D0 or no D
//                is not a nose, an insert is never sharp), else the scenario's [tool];
//   orientation: the tool table's Q when the table lists the tool, else the scenario's [tool].
//                Q0 (or no Q) is what LinuxCNC makes of it: with a nose (D > 0) its centre, as
//                Q9 (rs274ngc's cutter compensation translates neither, latheorigin_x/z in
//                interp_queue.cc; AXIS draws no lathe tool for Q0); without one (D0) a point
//                tool, its point where the program puts it (a radius of 0 translates nothing),
//                which on the nose taken from elsewhere is the scenario's tip.
//   front and back angle (the insert's straight edges, cutting::straight_edges_of): the tool
//                table's I and J where either is non-zero, else the scenario's [tool]
//                front_angle_deg and back_angle_deg (both 0: the nose alone).
// Never allocates or throws (the plant calls it in its real-time update at a tool change).
struct ToolGeometry {
  double nose_radius_mm = 0.0;
  int orientation = 0;
  double front_angle_deg = 0.0;  // LinuxCNC's I [°]
  double back_angle_deg = 0.0;   // LinuxCNC's J [°]
};
ToolGeometry tool_geometry(const std::vector<ToolSpec>& specs,
                           const std::vector<TableTool>& table, int number,
                           const ToolGeometry& scenario) noexcept;
// The largest nose radius tool_geometry() gives any tool of the two lists (the scenario's
// included): what the plant's scratch is sized for (cutting::LathePlant::Params).
double largest_nose_radius_mm(const std::vector<ToolSpec>& specs,
                              const std::vector<TableTool>& table, double scenario_mm) noexcept;

}  // namespace lathectl::io
