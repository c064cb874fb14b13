#pragma once
// A LinuxCNC INI file (the user's machine: `lathectl optimize --ini FILE`) as LinuxCNC's
// IniFile reads it: `[SECTION]` lines, `KEY = VALUE` lines within a section, whole-line comments
// starting with '#' or ';', blanks around keys and values ignored; the first of a repeated key
// is the one LinuxCNC finds. What a lathe's program needs of it is `lathe_machine`: the units,
// the X and Z soft limits, velocity and acceleration, in millimetres, and the tool table's name.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lathectl::io {

struct LinuxcncIni {
  struct Entry {
    std::string section, key, value;
    int line = 0;
  };
  std::string file;
  std::vector<Entry> entries;
  // The first `key` of `[section]`; nullptr when absent.
  [[nodiscard]] const Entry* find(std::string_view section, std::string_view key) const;
};

// Never throws: a line that is not a section, a key = value or a comment is passed over, as
// LinuxCNC passes over it.
LinuxcncIni parse_linuxcnc_ini(std::string_view text, const std::string& file);

// A lathe's machine as lathectl optimize and its --verify use it; every length in mm.
struct LatheMachine {
  double unit_mm = 1.0;  // [TRAJ]LINEAR_UNITS: 1 (mm, metric), 25.4 (inch, in, imperial)
  std::optional<double> x_min, x_max, z_min, z_max;  // [AXIS_X], [AXIS_Z] MIN_LIMIT, MAX_LIMIT
  // The least of [TRAJ]MAX_LINEAR_VELOCITY / _ACCELERATION and [AXIS_X], [AXIS_Z] MAX_VELOCITY /
  // MAX_ACCELERATION given (mm/s, mm/s²); nullopt when none is.
  std::optional<double> max_velocity_mm_s, max_acceleration_mm_s2;
  std::string tool_table;  // [EMCIO]TOOL_TABLE as written ("" when absent)
  // [EMCIO]TOOL_CHANGE_POSITION's X and Z ("X Y Z [A B C [U V W]]", machine coordinates, X the
  // radius; Y and the rest a lathe does not have): where LinuxCNC's task moves the tool at each M6
  // before the change (emccanon.cc CHANGE_TOOL); nullopt when the INI gives none.
  std::optional<double> tool_change_x, tool_change_z;
  // Where homing leaves X's and Z's joints: [JOINT_n]HOME (LinuxCNC's default 0 when absent),
  // n the joint of the axis ([KINS]KINEMATICS trivkins coordinates=…, else X 0, Z 2); the key
  // ("[JOINT_1]HOME") and its line (0 when absent), for messages. HOME_OFFSET (the home switch's
  // position) is checked as a number; after homing the joint stands at HOME (homing.c).
  double home_x = 0.0, home_z = 0.0;
  std::string home_x_key, home_z_key;
  int home_x_line = 0, home_z_line = 0;
};
// Throws InputError naming the file, line, section and key of a value that is not what LinuxCNC
// takes (a unit it does not know, a limit that is not a finite number, a velocity or
// acceleration ≤ 0, MIN_LIMIT above MAX_LIMIT, a TOOL_CHANGE_POSITION that is not three or more
// numbers, a HOME or HOME_OFFSET that is not a number), or the file, section and key of a missing
// [TRAJ]LINEAR_UNITS.
LatheMachine lathe_machine(const LinuxcncIni& ini);

}  // namespace lathectl::io
