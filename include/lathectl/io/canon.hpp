#pragma once
// LinuxCNC's canonical machining commands as its standalone interpreter prints them
// (`rs274 -g -t TOOLS -v VARS PROGRAM`, src/emc/sai/saicanon.cc): one command a line,
//
//     <seq> N<word>|N..... NAME(args)
//
// read into the moves of a turning program (plane XZ, X the radius, millimetres: rs274 prints a
// G20 program's lengths, feeds and thread pitches in inches and its G96 surface speed in feet
// per minute, each converted here as LinuxCNC's canon converts it, by the units in force when
// the command comes). What LinuxCNC
// runs is what is read: G7x cycles, subroutines, loops and cutter compensation arrive expanded.
// The program line of a move comes from a marker comment, "(lathectl-line N)", that the caller
// puts on each line of the copy it interprets (rs274 prints a line's last comment as
// COMMENT("…") before the line's motion; the lines of a subroutine a G7x cycle reads print none,
// so a cycle's moves belong to the cycle's line).
//
//   STRAIGHT_TRAVERSE(x, y, z, a, b, c)        G0
//   STRAIGHT_FEED(x, y, z, a, b, c)            G1 (and the straight pieces of G7x/G33/G76)
//   ARC_FEED(z1, x1, zc, xc, rot, y, a, b, c)  in CANON_PLANE_XZ: first axis z, second x;
//                                              rot < 0 clockwise (G2), > 0 counter-clockwise (G3)
//   SET_FEED_MODE(spindle, 0|1)                G94 | G95
//   SET_FEED_RATE(f)                           mm/min (G94) or mm/rev (G95)
//   SET_SPINDLE_MODE(spindle css_max)          0: G97; > 0: G96 with D css_max [rpm]
//   SET_SPINDLE_SPEED(spindle, s)              rpm (G97) or m/min (G96)
//   START_SPINDLE_(COUNTER)CLOCKWISE, STOP_SPINDLE_TURNING
//   START_SPEED_FEED_SYNC(pitch, css) / STOP_SPEED_FEED_SYNCH
//                                              G33/G33.1/G76 threading: mm per revolution
//   SET_G5X_OFFSET(n, x, y, z, …), SET_G92_OFFSET(x, y, z, …), USE_TOOL_LENGTH_OFFSET(x y z, …)
//                                              what lies between the program's coordinates
//                                              and the machine's (the soft limits are the latter)
//   SELECT_TOOL(t), COMMENT("…"), USE_LENGTH_UNITS(CANON_UNITS_MM|_INCHES)
// Anything else is passed over. Arcs outside the XZ plane are refused.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lathectl::io {

struct CanonMove {
  enum class Kind { Traverse, Line, Arc };
  Kind kind = Kind::Line;
  int line = 0;                                   // program line (the marker), 0 when none was seen
  double x0 = 0.0, z0 = 0.0, x1 = 0.0, z1 = 0.0;  // start and end: radius, z [mm]
  // The program's length unit at this move [mm]: 25.4 under G20, 1 under G21 (what a line
  // written for it divides by).
  double unit_mm = 1.0;
  double xc = 0.0, zc = 0.0;                      // arc centre
  int rotation = 0;                               // arc: < 0 G2, > 0 G3
  bool per_rev = false;                           // G95
  double feed = 0.0;                              // mm/rev (G95) or mm/min (G94); 0 before any F
                                                  // (an inch program's F × 25.4)
  bool css = false;                               // G96
  double css_max_rpm = 0.0;                       // G96's D
  double speed = 0.0;                             // rpm (G97) or m/min (G96)
  bool spindle_on = false;
  bool synced = false;       // threading: spindle-synchronised
  double pitch_mm = 0.0;     // threading: the tool's advance per revolution (G33 K, G76 P)
  // The machine position is the move's plus this (work offset G5x, G92 and tool length offset):
  // x (radius) and z [mm].
  double offset_x = 0.0, offset_z = 0.0;
  bool compensated = false;  // cutter radius compensation on (G41/G42/G41.1/G42.1)
  int tool = 0;
  // Path blending (SET_MOTION_CONTROL_MODE): G64's P [mm], 0 when none was given (LinuxCNC's
  // default, continuous with no tolerance); < 0: exact path or exact stop (G61, G61.1).
  double blend_tol_mm = 0.0;
  // Something between the previous move and this one makes LinuxCNC stop (a dwell, a tool
  // change, a spindle command, a program stop, an M1xx): no blend across it.
  bool stop_before = false;
  // LinuxCNC's own travel at an M6 to the INI's [EMCIO]TOOL_CHANGE_POSITION (a Traverse the
  // program does not write: parse_canon's tool_change), on the M6's line with the tool leaving.
  bool tool_change = false;
};

struct CanonProgram {
  std::vector<CanonMove> moves;
};

// The marker comment for program line `line` ("lathectl-line 12").
std::string canon_line_marker(int line);

// The machine's [EMCIO]TOOL_CHANGE_POSITION, X (radius) and Z in machine coordinates [mm].
struct ToolChangePosition {
  double x_mm = 0.0, z_mm = 0.0;
};

// Reads rs274's output. `label` names the program in messages; start: the tool's position
// before the first move (x, z). With `tool_change`, each CHANGE_TOOL (M6) is preceded by what
// LinuxCNC's task adds there and rs274 does not print (emccanon.cc CHANGE_TOOL): a straight
// rapid of all axes together, from rest to rest, to that machine position (the program's
// coordinates: minus the offsets in force), from where the next move starts. Throws
// InputError, one line, on what it cannot read.
CanonProgram parse_canon(std::string_view text, const std::string& label, double start_x_mm = 0.0,
                         double start_z_mm = 0.0,
                         std::optional<ToolChangePosition> tool_change = std::nullopt);

}  // namespace lathectl::io
