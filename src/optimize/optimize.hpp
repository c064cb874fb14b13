#pragma once
// `lathectl optimize PROGRAM.ngc SCENARIO.toml --out DIR [--verify]`: offline feed optimisation
// of a turning NC program on a system-E scenario's blank.
//
//   1. LinuxCNC's own interpreter (rs274) reads the program (interpret): the moves as LinuxCNC
//      runs them, each with its program line (io::parse_canon).
//   2. predict: the moves are run through cutting::LathePlant, the cutting process the LinuxCNC
//      plant component (hal/lathectl_plant) runs, at its servo period: the same stock
//      bookkeeping, cutting model and disturbances, so depth, chip, Pz/Py/power, torque, time and
//      tool-life use per move are what the plant will produce.
//   3. plan: each feed move is cut into pieces where its engagement changes; each piece gets the
//      largest feed per revolution that keeps the force parameter, the cutting power and the
//      spindle torque within the scenario's limits and the feed within [feed_min, feed_max];
//      pieces in air get the air feed, finishing pieces (depth ≤ finish depth) at most the feed
//      of the roughness Ra = f²/(32 r_ε); threading (spindle-synchronised) and lines marked
//      "(lathectl:keep)" are left alone.
//   4. write: optimized.ngc keeps the program's lines, with changed F words; a line whose pieces
//      need different feeds is split (pieces inserted before it, marked by comments) or, for a
//      cycle (G7x) line, expanded into its moves. The result is interpreted again and must follow
//      the original path; if it does not (modes the pieces cannot be written in: G91, G7, offsets,
//      cutter compensation), the splits are dropped and each line gets one F.
//
// This header has no optimize.cpp: it declares what the four libraries of `lathectl optimize`
// share (CMakeLists.txt), each part defined in its own: Options, Program and the interpreter's
// run in program.cpp (lathectl_optimize_interpret); Piece … Prediction, predict, programmed and
// the leg times in predict.cpp (lathectl_optimize_predict); Result and optimize in rewrite.cpp,
// the warnings, blend note and output files in outputs.cpp (lathectl_optimize_plan); verify in
// verify.cpp (lathectl_optimize_verify).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/io/canon.hpp"
#include "lathectl/io/linuxcnc_ini.hpp"
#include "optimize/blend.hpp"
#include "optimize/tools.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::optimize {

struct Options;
// The tool `number` cuts with in the prediction (io::tool_geometry, the LinuxCNC plant's
// choice): --tool-file's nose_radius_mm, else the tool table's D/2, else the scenario's [tool]
// nose_radius_mm; the tool table's Q (Q0 with D > 0: the nose's centre, as LinuxCNC) when the
// table lists the tool, else the scenario's [tool] orientation; the insert's front and back
// angle from the table's I and J where it gives either, else the scenario's [tool]
// front_angle_deg and back_angle_deg.
io::ToolGeometry tool_geometry(const Options& opt, const systems::e_adaptive::Settings& e,
                               int number);
// The largest nose of them all (the plant's scratch, LathePlant::Params::max_nose_radius_mm).
double largest_nose_radius_mm(const Options& opt, const systems::e_adaptive::Settings& e);

struct Options {
  double spindle_rpm = 0.0;      // > 0: "M3 S<rpm>" before the program (as linuxcnc-sim)
  double z_origin_mm = 0.0;      // machine z of the stock's z = 0 (as linuxcnc-sim)
  double air_feed = -1.0;        // mm/rev in air; < 0: the controller's feed_max
  double finish_depth_mm = 0.6;  // a piece at most this deep is finishing
  // Roughness a finishing feed keeps: 0, the programmed feed's; a value, a smoother target (a
  // finishing feed is never above the programmed one).
  double finish_ra_um = 0.0;
  double limit_fraction = 0.97;  // the feed is chosen for this share of each limit
  std::string rs274 = "rs274";   // LinuxCNC's standalone interpreter
  // Bounds on the interpreter (an endless o-word loop runs for ever and writes ~45 MB/s): its
  // time [s] and the size of its canonical output [bytes]; past either it is killed.
  double interp_timeout_s = 60.0;
  std::uintmax_t interp_output_max_bytes = 512u * 1024u * 1024u;
  // A rapid through material is an error unless allowed (then the report says so first, and
  // the feed moves after it keep their programmed feeds: the stock model no longer knows what
  // is left of the blank).
  bool allow_rapid_in_material = false;
  // The T numbers the scenario's [tool] describes (empty: the tool of the first feed move).
  // Feed moves of any other tool keep their programmed feeds: their insert, width and feed
  // range are not known.
  std::vector<int> tools;
  // The program's other tools (--tool-file, tools.hpp): kind, insert width, feed range.
  std::vector<ToolSpec> tool_specs;
  std::string ini;         // the machine's INI (--ini; default the simulated lathe's)
  std::string tool_table;  // LinuxCNC's tool table (empty: the INI's [EMCIO]TOOL_TABLE)
  // Its tools as read (read_tool_table): each one's nose (D/2) and orientation Q (where the
  // programmed point is on it; tool_geometry); empty: every tool has the scenario's [tool].
  std::vector<TableTool> table_tools;
  double start_x_mm = 60.0;      // where the tool stands before the program (the sim's home)
  double start_z_mm = 60.0;
  Machine machine;      // the planner's limits for the blends (blend.hpp)
  bool blends = true;   // predict LinuxCNC's G64 blend arcs (false: the programmed corners)
  // Predict the program run with system E's machine side on (lathectl_adaptive in LinuxCNC:
  // control::AdaptiveMachine, the same object), its feed factor scaling every feed move, at
  // the sample configuration's MAX_FEED_OVERRIDE of 1 (never above the program's feed).
  bool adaptive = false;
  std::string label;  // the program's file, for messages
};

// The program's lines and what rs274 made of them.
struct Program {
  std::string file;
  std::vector<std::string> lines;  // the text, line 1 at [0]
  io::CanonProgram canon;
};

// A word for /bin/sh ('…'), and a file's text ("" when unreadable): for running rs274 and the
// simulator.
std::string shell_quote(const std::string& s);
std::string read_text(const std::filesystem::path& p);

// Runs rs274 on `text` (lines marked for io::parse_canon); InputError naming `label` and the
// line on an interpreter error.
io::CanonProgram interpret(const std::vector<std::string>& lines, const std::string& label,
                           const Options& opt);
Program read_program(const std::string& path, const Options& opt);
// LinuxCNC's tool table with its lengths (D, X Y Z U V W) times `factor` (an inch table for the
// millimetre simulated lathe: 25.4), its angles, numbers, orientation and comments as they were.
std::string tool_table_scaled(const std::string& text, double factor);
// The INI's [EMCIO]TOOL_TABLE, relative to the INI's folder as LinuxCNC takes it; InputError
// naming the INI when it has none.
std::string machine_tool_table(const std::string& ini_file, const io::LatheMachine& mc);
// InputError naming the line of the first move beyond the INI's soft limits ([AXIS_X] and
// [AXIS_Z] MIN_LIMIT/MAX_LIMIT, in machine coordinates: the move plus its offsets), which
// LinuxCNC refuses to run. read_program checks it when Options::ini is set.
void check_soft_limits(const Program& p, const std::string& ini_file);

// Where the tool stands when the program starts on the user's machine (--ini): where LinuxCNC's
// homing leaves it, [JOINT_n]HOME of X's and Z's joints (0 when absent), when that lies clear
// of the blank: above its largest radius (eccentricity included) or in front of its face, by
// the nose's width (2·r_ε) at least. Else the simulated lathe's start (Options::start_x_mm,
// start_z_mm) and `note`, one line naming the INI's file, line and key: the simulated lathe has
// no work offsets, so a home inside the blank (LinuxCNC's own sim/axis/lathe.ini has no HOME:
// X0 Z0, the face's centre) would start the tool in the material.
struct MachineStart {
  double x_mm = 0.0, z_mm = 0.0;
  bool from_ini = false;  // the INI's home is taken
  std::string note;       // why it is not ("" when it is)
};
MachineStart machine_start(const io::LatheMachine& mc, const std::string& ini_file,
                           const systems::e_adaptive::Settings& e, const Options& opt);

// A piece of a move at one feed: the share [from, to] of the move's length.
struct Piece {
  double from = 0.0, to = 1.0;
  double feed = 0.0;       // mm/rev (G95) or mm/min (G94), as the move's F
  std::string limited_by;  // "force", "power", "torque", "feed_max", "roughness", "air", ...
  int out_line = 0;        // its line in optimized.ngc
};
using Plan = std::vector<std::vector<Piece>>;  // per move

// The prediction along the program: one sample per servo period in feed moves and rapids, at
// most kMaxPredictedSamples of them (an hour of the program at 1 ms, about 0.55 GB a
// prediction): a longer program is refused at its slowest move before one is taken.
inline constexpr double kMaxPredictedSamples = 3.6e6;
// The canonical moves a program may have (read_program): about 0.8 GB of what optimize holds.
inline constexpr std::size_t kMaxProgramMoves = 500'000;
struct Samples {
  double dt_s = 0.001;
  std::vector<int> move, piece;
  std::vector<double> path_mm, depth, feed_rev, speed, rpm, strength, param, pz, py, power, torque,
      life_use, x, z, dt, wear;  // x: radius, z: machine z [mm]
  // With the scenario's [chatter] (chatter.hpp), per sample in cut, NaN elsewhere; else empty:
  std::vector<double> kcrit;   // k_lim: the largest stable cutting stiffness ∂Pz/∂s [N/m]
  std::vector<double> margin;  // chatter margin: limit depth / depth
};
struct MoveStats {  // per move and piece
  double time_s = 0.0, depth_max = 0.0, param_mean = 0.0, param_max = 0.0, power_max = 0.0,
         torque_max = 0.0, life_use = 0.0, feed_rev_mean = 0.0;
  int n = 0, n_cut = 0;
};
struct Prediction {
  Samples s;
  double cycle_time_s = 0.0;  // the samples' time plus accel_time_s
  // What the planner's acceleration (trapezoidal, from and to the stops and slower segments)
  // adds to the cycle; in cycle_time_s, not in the samples nor the per-block times.
  double accel_time_s = 0.0;
  double life_use = 0.0;  // share of the tool's life (Palmgren–Miner)
  double rapid_in_material_s = 0.0;
  double rapid_peak = 0.0;
  int rapid_first_line = 0;
  // LinuxCNC's blend arcs in material: the largest distance inside the programmed corner [mm]
  // and the line whose end that corner is (0: none).
  double blend_inside_max_mm = 0.0;
  int blend_inside_line = 0;
  // With Options::adaptive: the machine side's commanded feed per revolution [mm/rev] and its
  // feed factor per sample (empty otherwise), and its first alarm's reason code (0: none).
  std::vector<double> adaptive_feed_rev, adaptive_factor;
  int adaptive_alarm = 0;  // The workpiece's radius [mm] before and after the program, at machine z part_z [mm] (for
  // the review's tool-path picture).
  std::vector<double> part_z, blank_r, part_r;
};
Prediction predict(const io::CanonProgram& prog, const Plan& plan,
                   const systems::e_adaptive::Settings& e, const Options& opt);

// The planner's velocity profile over a program's legs (segments and blend arcs, in order):
// each run at its velocity v [mm/s] over len [mm] with acceleration a [mm/s²]; stop_after: the
// planner stops at its end.
struct Leg {
  double len, v, a;
  bool stop_after;
};
// The time of one leg entered at v0 and left at v1 (≤ v): a trapezoid, or a triangle when it
// is too short to reach v.
double leg_time(double len, double v, double v0, double v1, double a);
// What accelerating and braking add to Σ len / v over the legs: from rest at the start, to rest
// at the end and at every stop, and between legs of different velocities.
double acceleration_time(const std::vector<Leg>& legs);

struct LineAction {
  enum class Kind { None, Keep, Feed, Split, Expand };
  Kind kind = Kind::None;
  std::string why;  // for Keep
  bool changed = false;  // counted in Result::blocks_changed: split, expanded, or its F changed
};
struct Result {
  Plan original, optimized;
  Prediction before, after;
  std::vector<LineAction> actions;  // per program line (index line − 1)
  std::string ngc;
  bool splits_dropped = false;
  int blocks_changed = 0;
  double limit = 0.0;  // the force parameter's limit (N, or W)
  bool chatter = false;  // the scenario has modes: the samples carry the chatter margin
};
Result optimize(const Program& p, const systems::e_adaptive::Settings& e, const Options& opt);

// The plan with the programmed feeds, one piece per move.
Plan programmed(const io::CanonProgram& prog);

}  // namespace lathectl::optimize

namespace lathectl::optimize {

// --verify: the programs run in LinuxCNC's simulated lathe with the plant in the loop
// (scripts/linuxcnc-sim): original and optimised with the adaptive controller off ("M68 E3 Q1"
// in front), and both with seed 004's online control on (the simulator's default).
struct VerifyRun {
  std::string name;  // "original", "optimized", "original_online", "optimized_online"
  bool finished = false;
  bool retried = false;  // LinuxCNC's task exited in the first attempt: run once more
  double cycle_time_s = 0.0;
  double force_peak_rev = 0.0;  // peak of the per-revolution mean of the true force parameter
                                // in feed moves
  double rapid_in_material_s = 0.0;
  double rapid_peak = 0.0;
  std::string summary_json;          // the simulator's summary.json
  std::vector<double> t, force_rev;  // for the report (feed moves and rapids alike)
  std::vector<int> line;             // the program line of each sample (the run's program)
  std::vector<double> force, motion;
  std::vector<double> x, z;  // the tool's position [mm] (radius, machine z)
};
struct Verified {
  std::vector<VerifyRun> runs;
  double prediction_error_pct = 0.0;  // largest |predicted − measured| mean per line (≥ 0.3 s), % of limit
  int prediction_error_line = 0;      // its line in optimized.ngc
  int lines_compared = 0;
};
struct VerifyOptions {
  std::vector<std::string> sim;  // the simulator's command (may start with a wrapper: flock …)
  std::string scenario;          // the scenario file
  double timeout_s = 1200.0;
  // The user's machine (--ini): the simulated lathe takes its soft limits, velocity and
  // acceleration (mm), not its HAL files.
  std::optional<io::LatheMachine> machine;
  // The tool table of --ini or --tool-table (in the machine's units; empty: the simulated
  // lathe's own): the simulated lathe's, in mm, so its plant cuts each tool's nose and Q as
  // the prediction did.
  std::string tool_table_text;
  // The tool file (--tool-file; empty: none): the simulated lathe's plant cuts its grooving and
  // parting tools with their inserts' width, as the prediction does (linuxcnc-sim --tool-file).
  std::string tool_file;
};
Verified verify(const Program& p, const Result& r, const Options& opt, const VerifyOptions& v);

// What a programmer must read first (the report's verdict, WARNING lines on the console): a
// rapid through material, a predicted peak above the limit (a line kept as written), pieces
// predicted to chatter.
std::vector<std::string> warnings(const Program& p, const systems::e_adaptive::Settings& e,
                                  const Result& r);

// What a rapid through material on `line` is, for messages: "a rapid (G0)", or, when the line's
// only rapid is LinuxCNC's travel at its M6, "LinuxCNC's travel to [EMCIO]TOOL_CHANGE_POSITION
// at the M6".
std::string rapid_what(const io::CanonProgram& prog, int line);

// A note for a program whose G64 blends cut inside its contour in material (blend.hpp).
std::string blend_note(const Prediction& p);

// The output set: optimized.ngc, blocks.csv, summary.json, report.html (+ the runs' summaries).
std::vector<std::pair<std::string, std::string>> output_files(
    const Program& p, const Result& r, const systems::e_adaptive::Settings& e, const Options& opt,
    const std::string& scenario_file, const Verified* v);

}  // namespace lathectl::optimize
