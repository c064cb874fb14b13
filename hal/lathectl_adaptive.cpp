// lathectl_adaptive — the system-E adaptive controller (seed 004: force held by the feed, cutting
// speed by V_opt = V_p·(S_p/S_cur)^y_v) as a realtime HAL component. A thin wrapper: the control
// law is control::AdaptiveFeedController, the same object file the simulator links.
//
//   loadrt lathectl_adaptive scenario=PATH [tools=PATH] [taught=PATH] [sensor=force|power]
//   addf lathectl-adaptive servo-thread
//
// The controller's settings come from the scenario's [controller] and [sensor] sections (the
// same file `lathectl run` reads). Its feed per revolution becomes motion.adaptive-feed as the
// ratio to the program's feed per revolution (requested velocity / spindle speed), clamped to
// [0, 1]: never negative (a negative factor runs the path backwards), never above the program.
// The cutting power the speed law limits is the one the rig computes (control::adaptive_input):
// from Pz·V, from the power sensor itself, or, with a Py sensor, from spindle-power minus the
// scenario's idle power.
//
// A shop's settings per operation (Heidenhain AFC's, on LinuxCNC's conventions):
//   - from the NC program, on motion's analog outputs (M68 E<n> Q<v>, or M67 to set it at the
//     start of the next move without stopping): E0 the limit (N, or W with sensor=power), E1/E2
//     the feed bounds [mm/rev], E3 the mode (0 the tool table's, 1 off, 2 on, 3 teach, 4 on at
//     E0 % of the taught reference), E4 the operation number the teach-in is stored under; 0
//     means "not set": the per-tool table's value (tools=, keyed by iocontrol.0.tool-number),
//     else the scenario's. A value is in effect in the servo period after motion puts it out.
//   - a bad value (negative, NaN, above the rating, not a mode) is never used: the last good
//     settings stay, the feed holds (feed-hold, adaptive-feed 0) and bad-code/bad-line/bad-value
//     tell lathectl_oplog, which gives the operator the message naming the program line.
//   - sensor=power: the load is the spindle drive's power pin minus the idle power P_idle(n),
//     learned (control::IdleTare) outside feed moves at steady speed, times the drive's
//     efficiency: the cutting power at the spindle.
//   - teach-in (E3 = 3): the program's feed (adaptive-feed 1) and the mean load over the steady
//     cut (control::TeachIn) published on the teach-* pins; lathectl_oplog stores it (taught=).
//   - one operation record per program line with feed moves on the op-* pins (op-seq counts).
//   - the latching detectors count the period measured between calls (rtapi_get_time()), not the
//     thread's nominal one: a late servo period is neither a breakage nor a stuck sensor.
//   - the tool's number, offsets or table row changing inside a feed move (another LinuxCNC
//     program rewrote the tool table under this one): alarm 22, not a breakage (ToolWatch).
// Pins, parameters and units: lathectl_adaptive(9).

#include <algorithm>
#include <array>
#include <memory>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/control/adaptive_input.hpp"
#include "lathectl/control/operation_control.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl_hal.hpp"
#include "lathectl_tool_limits.hpp"
#include "systems/e_adaptive/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-E adaptive feed and cutting-speed controller for LinuxCNC");
MODULE_LICENSE("GPL");

static char* scenario = nullptr;
RTAPI_MP_STRING(scenario,
                "system-E scenario file (TOML) whose [controller] and [sensor] set the controller");
static char* tools = nullptr;
RTAPI_MP_STRING(tools, "per-tool limits table (TOML, optional): rating, defaults, overload levels");
static char* taught = nullptr;
RTAPI_MP_STRING(taught, "teach-in references (TOML written by lathectl_oplog; absent: none)");
static char* z_origin_mm = nullptr;
RTAPI_MP_STRING(z_origin_mm,
                "machine z of the stock's face: turns on the stock model for the "
                "path-aware breakage detector (unset: the controller's own)");
static char* sensor = nullptr;
RTAPI_MP_STRING(sensor, "force (the scenario's sensor, default) or power (spindle-power - idle)");

namespace {

using lathectl::control::AdaptiveFeedController;
using lathectl::control::SettingError;
constexpr const char* kName = "lathectl_adaptive";
constexpr const char* kPrefix = "lathectl-adaptive";
constexpr std::size_t kMaxTools = 64;
constexpr std::size_t kMaxTaught = 256;
// The feed scale's resolution: halui.feed-override.scale with direct-value (the sample config).
constexpr double kOverrideStep = 0.001;
constexpr double kRescaleAfter = 0.5;  // [s], well beyond halui's measured 0.1-0.2 s
constexpr double kRescaleFor = 0.05;   // [s], over two of halui's 20 ms loops

struct Pins {
  // inputs
  hal_float_t* force;
  hal_float_t* rpm;
  hal_float_t* rpm_programmed;
  hal_float_t* current_vel;
  hal_float_t* requested_vel;
  hal_float_t* feed_upm;  // motion.feed-upm: the F word of the move × motion's net scale
  hal_s32_t* motion_type;
  hal_float_t* x_pos;
  hal_float_t* cutting_speed;
  hal_float_t* spindle_power;
  hal_bit_t* per_rev;
  hal_bit_t* enable;
  hal_bit_t* reset;
  hal_float_t* limit_cmd;        // motion.analog-out-00
  hal_float_t* feed_min_cmd;     // -01
  hal_float_t* feed_max_cmd;     // -02
  hal_float_t* mode_cmd;         // -03
  hal_float_t* op_cmd;           // -04
  hal_s32_t* tool_number;        // iocontrol.0.tool-number
  hal_s32_t* program_line;       // motion.program-line
  hal_float_t* z_pos;            // joint 1 (the stock model's path)
  hal_bit_t* homed;              // motion.is-all-homed (positions mean something; HomedGate)
  hal_float_t* knob;             // the operator's feed override (panel, MPG)
  hal_float_t* max_override;     // [DISPLAY]MAX_FEED_OVERRIDE
  hal_float_t* scale_in_motion;  // halui.feed-override.value (motion's feed scale)
  // outputs
  hal_float_t* adaptive_feed;
  hal_float_t* feed_override;       // motion's feed scale to command
  hal_s32_t* feed_override_counts;  // the same in thousandths (halui.feed-override.counts)
  hal_float_t* feed_factor;         // the net override of the program's feed
  hal_float_t* spindle_speed_out;
  hal_float_t* spindle_override;
  hal_bit_t* feed_hold;
  hal_bit_t* alarm;
  hal_s32_t* reason;
  hal_s32_t* alarm_reason;
  hal_float_t* feed_per_rev;
  hal_float_t* speed_cmd;
  hal_float_t* speed_opt;
  hal_float_t* cut_power;
  hal_bit_t* in_cut;
  hal_bit_t* period_error;
  hal_s32_t* update_ns;
  hal_s32_t* update_ns_max;
  hal_bit_t* reset_max;
  hal_float_t* load;  // the load the controller sees (N, or W with sensor=power)
  hal_float_t* limit;
  hal_float_t* feed_min_out;
  hal_float_t* feed_max_out;
  hal_bit_t* adaptive_on;
  hal_bit_t* teaching;
  hal_float_t* idle_power;
  hal_bit_t* tare_ready;
  hal_float_t* idle_p[3];
  hal_bit_t* bad_setting;
  hal_s32_t* bad_code;
  hal_s32_t* bad_line;
  hal_float_t* bad_value;
  hal_bit_t* overload_warn;
  hal_bit_t* overload_hold;
  hal_float_t* load_rev;         // the load's mean over the last revolution
  hal_float_t* load_pct;         // load_rev in % of the limit (the operator panel's bar)
  hal_float_t* predicted_depth;  // the stock model's depth of cut at the tool [mm]
  hal_bit_t* breakage;           // path-aware breakage alarm (latched)
  hal_float_t* tool_diameter;    // halui.tool.diameter (the tool table's row of the tool)
  hal_float_t* tool_offset_x;    // motion.tooloffset.x (the offset in effect)
  hal_float_t* tool_offset_z;    // motion.tooloffset.z
  hal_bit_t* tool_data_changed;  // the tool's data changed during a feed move (latched)
  hal_s32_t* op_seq;
  hal_s32_t* op_line;
  hal_s32_t* op_tool;
  hal_s32_t* op_number;
  hal_s32_t* op_mode;
  hal_float_t* op_limit;
  hal_float_t* op_mean;
  hal_float_t* op_peak;
  hal_float_t* op_feed_min;
  hal_float_t* op_feed_mean;
  hal_float_t* op_time_cut;
  hal_float_t* op_time;
  hal_s32_t* op_reasons;
  hal_s32_t* op_alarm;
  hal_s32_t* teach_seq;
  hal_s32_t* teach_tool;
  hal_s32_t* teach_op;
  hal_float_t* teach_ref;
  // parameters (read-only: the scenario's settings)
  hal_float_t force_limit;
  hal_float_t feed_min;
  hal_float_t feed_max;
  hal_float_t feed_programmed;
  hal_float_t speed_programmed;
  hal_float_t control_period;
  hal_float_t rating;
};

struct TaughtRef {
  int tool = -1;
  int op = 0;
  double ref = 0.0;
};

// The settings an operation runs with, resolved from the program, the tool table, the scenario.
struct OpSettings {
  double limit = 0.0;
  double feed_min = 0.0;
  double feed_max = 0.0;
  int mode = 2;  // 1 off, 2 on, 3 teach (4 resolves to 2 with the limit from the reference)
  double reference = 0.0;  // what overload levels are percentages of
  bool operator==(const OpSettings&) const = default;
};

// Tool data under a running program. Task changes the tool (M6: iocontrol.0.tool-number) and
// its offsets (G43, G10 L1: motion.tooloffset.*) only with motion stopped between moves
// (emctaskmain.cc, emcTaskCheckPreconditions: WAITING_FOR_MOTION), so none of them changes in a
// feed move of a program. halui.tool.diameter is the tool table's row of the tool in the spindle,
// read from the table every machine shares (the tool data map $HOME/.tool.mmap) — which
// LinuxCNC 2.9's standalone rs274, run as the same user, recreates with its own tools under a
// running program. A change in a feed move is therefore not the program's: the part is being cut
// by other data than it was programmed for, and a load that falls or rises then says nothing
// about the tool's edge. halui publishes the diameter in its own loop, after iocontrol's tool
// number: a change within kToolSettleS of a tool change is that change arriving.
constexpr double kToolSettleS = 1.0;
struct ToolWatch {
  int tool = 0;
  double diameter = 0.0, offset_x = 0.0, offset_z = 0.0;
  double since_change_s = 1e9;  // since the tool number last changed
  bool known = false;
  // One servo period; true when the data changed inside a feed move.
  bool update(int t, double d, double ox, double oz, bool feed_move, double dt) noexcept {
    since_change_s = t != tool ? 0.0 : since_change_s + dt;
    const bool settling = since_change_s < kToolSettleS;
    const bool moved = known && (t != tool || std::abs(d - diameter) > 1e-6 ||
                                 std::abs(ox - offset_x) > 1e-6 || std::abs(oz - offset_z) > 1e-6);
    const bool changed =
        feed_move && moved &&
        !(settling && t == tool && ox == offset_x && oz == offset_z);  // halui's late diameter
    tool = t;
    diameter = d;
    offset_x = ox;
    offset_z = oz;
    known = true;
    return changed;
  }
};

struct State {
  AdaptiveFeedController ctl;
  AdaptiveFeedController::Output out{};
  lathectl::cutting::ForceParameter parameter = lathectl::cutting::ForceParameter::Pz;
  lathectl::drives::SpindleDrive::Params spindle;  // its idle law
  bool speed_law = false;
  bool power_sensor = false;
  long every = 0;  // thread periods per control period (0: not yet known)
  long count = 0;
  bool last_reset = false;
  // motion.requested-vel turns to the next block's value one period before motion.motion-type
  // does (seen at a G1 → G0 change: for one period the rapid's 80 mm/s read as the G95 feed);
  // a value is used once it has held for one thread period.
  double req_prev = 0.0;
  double req_stable = 0.0;
  // The F word under G95, from motion.feed-upm (below): 0 while motion's net scale is 0.
  double f_word = 0.0;
  lathectl::hal::HomedGate homed_gate;
  // shop settings
  lathectl::control::OperationRating rating;
  AdaptiveFeedController::Params base;
  std::array<lathectl::hal::ToolLimits, kMaxTools> tools{};
  std::size_t n_tools = 0;
  std::array<TaughtRef, kMaxTaught> taught{};
  std::size_t n_taught = 0;
  OpSettings applied{};
  bool bad = false;
  lathectl::control::IdleTare tare;
  lathectl::control::TeachIn teach;
  int teach_tool = -1, teach_op = -1;
  lathectl::control::OperationStats stats;
  int op_line = -1, op_tool = -1, op_number = 0, op_mode = 0;
  double op_limit = 0.0;
  double op_feed_s = 0.0;  // time in feed moves on this line
  std::int32_t op_reasons = 0, op_alarm = 0;
  bool contact = false;
  double below_air_s = 0.0;
  double rev_phase = 0.0, rev_sum = 0.0, rev_n = 0.0, load_rev = 0.0;
  bool overload_latched = false;
  // The stock model (z_origin_mm given): the scenario's blank cut down by the tool's path; its
  // depth of cut is the engagement the path-aware breakage detector expects.
  std::unique_ptr<lathectl::cutting::LathePlant> stock;
  lathectl::control::PathBreakage breakage;
  bool breakage_latched = false;
  // The measured period (rtapi_get_time() at the last call, and at the last control update).
  long long last_ns = 0, last_ctl_ns = 0;
  // The tool's data of the last period, watched for a change inside a feed move (ToolWatch).
  ToolWatch tool_watch;
  bool tool_data_latched = false;
  bool tool_data_first = false;  // it was the first alarm (alarm-reason 22)
  // The feed scale motion reports against the one commanded: halui sends a value only when its
  // counts change, so a value another client set since (AXIS's slider sends its own when it
  // redraws) would stay. After kRescaleAfter of disagreement the counts step one down for
  // kRescaleFor (two changes halui sees), and halui sends the commanded value again.
  double scale_mismatch_s = 0.0;
  double rescale_s = 0.0;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::UpdateTimer timer;

void hold_all(Pins& p) {
  *p.adaptive_feed = 0.0;
  *p.feed_hold = 1;
  *p.alarm = 1;
  *p.spindle_speed_out = *p.rpm_programmed;
  *p.spindle_override = 1.0;
}

const lathectl::hal::ToolLimits* tool_of(const State& s, int number) noexcept {
  for (std::size_t i = 0; i < s.n_tools; ++i)
    if (s.tools[i].number == number) return &s.tools[i];
  return nullptr;
}

TaughtRef* taught_of(State& s, int tool, int op) noexcept {
  for (std::size_t i = 0; i < s.n_taught; ++i)
    if (s.taught[i].tool == tool && s.taught[i].op == op) return &s.taught[i];
  return nullptr;
}

// An analog output that must be a whole number (a mode, an operation): NaN or a fraction is bad.
bool whole(double v, double lo, double hi) noexcept {
  return std::isfinite(v) && v >= lo && v <= hi && v == std::floor(v);
}

// The program's settings, the tool table's, the scenario's, in that order. A bad value leaves
// `out` as it was and returns what is wrong (and the value).
SettingError resolve(State& s, const Pins& p, OpSettings& out, double& bad_value) noexcept {
  const auto* tl = tool_of(s, *p.tool_number);
  const double mode_v = *p.mode_cmd;
  bad_value = mode_v;
  if (!whole(mode_v, 0.0, 4.0)) return SettingError::Mode;
  const double op_v = *p.op_cmd;
  bad_value = op_v;
  if (!whole(op_v, 0.0, 99999.0)) return SettingError::Mode;
  int mode = static_cast<int>(mode_v);
  if (mode == 0) mode = tl != nullptr && !tl->adaptive ? 1 : 2;
  OpSettings o;
  o.mode = mode;
  const double lim_v = *p.limit_cmd;
  bad_value = lim_v;
  if (mode == 4) {
    if (!std::isfinite(lim_v)) return SettingError::LimitNotFinite;
    const double pct = lim_v != 0.0 ? lim_v : tl != nullptr ? tl->reference_pct : 100.0;
    if (!(pct > 0.0) || pct > s.rating.percent_max) return SettingError::Percentage;
    const auto* t = taught_of(s, *p.tool_number, static_cast<int>(op_v));
    if (t == nullptr) return SettingError::NotTaught;
    o.reference = t->ref;
    o.limit = pct / 100.0 * t->ref;
    bad_value = o.limit;
    if (const auto e = lathectl::control::check_limit(o.limit, s.rating); e != SettingError::None)
      return e;
    o.mode = 2;
  } else {
    if (const auto e = lathectl::control::check_limit(lim_v, s.rating); e != SettingError::None)
      return e;
    o.limit = lim_v > 0.0                        ? lim_v
              : tl != nullptr && tl->limit > 0.0 ? tl->limit
                                                 : s.base.force_limit;
    o.reference = o.limit;
    if (lim_v == 0.0 && mode == 3) o.reference = o.limit;
  }
  const double fmin_v = *p.feed_min_cmd, fmax_v = *p.feed_max_cmd;
  bad_value = std::isfinite(fmin_v) && fmin_v >= 0.0 ? fmax_v : fmin_v;
  if (lathectl::control::check_feeds(fmin_v, fmax_v, s.rating) != SettingError::None)
    return SettingError::FeedBounds;
  o.feed_min = fmin_v > 0.0                                     ? fmin_v
               : tl != nullptr && tl->feed_min_mm_per_rev > 0.0 ? tl->feed_min_mm_per_rev
                                                                : s.base.feed_min_mm_per_rev;
  o.feed_max = fmax_v > 0.0                                     ? fmax_v
               : tl != nullptr && tl->feed_max_mm_per_rev > 0.0 ? tl->feed_max_mm_per_rev
                                                                : s.base.feed_max_mm_per_rev;
  bad_value = o.feed_min;
  if (!(o.feed_min < o.feed_max)) return SettingError::FeedBounds;
  out = o;
  return SettingError::None;
}

// The operation that ended: its record on the op-* pins, op-seq last (lathectl_oplog reads the
// record when op-seq changes).
void publish_operation(State& s, Pins& p) noexcept {
  if (s.op_line > 0 && s.op_feed_s > 0.0) {  // lines with feed moves only
    *p.op_line = s.op_line;
    *p.op_tool = s.op_tool;
    *p.op_number = s.op_number;
    *p.op_mode = s.op_mode;
    *p.op_limit = s.op_limit;
    *p.op_mean = s.stats.mean_load();
    *p.op_peak = s.stats.peak_load();
    *p.op_feed_min = s.stats.feed_min();
    *p.op_feed_mean = s.stats.feed_mean();
    *p.op_time_cut = s.stats.time_in_cut_s();
    *p.op_time = s.stats.time_s();
    *p.op_reasons = s.op_reasons;
    *p.op_alarm = s.op_alarm;
    *p.op_seq = *p.op_seq + 1;
  }
  s.stats.reset();
  s.op_feed_s = 0.0;
  s.op_reasons = 0;
  s.op_alarm = 0;
}

void update(void*, long period_ns) {
  Pins& p = *pins;
  State& s = *st;
  if (s.every == 0) {  // the control period must be a whole number of thread periods
    const double ratio = s.ctl.params().period_s * 1e9 / static_cast<double>(period_ns);
    const long k = std::lround(ratio);
    if (k < 1 || std::abs(ratio - static_cast<double>(k)) > 0.01 * ratio) {
      s.every = -1;
      *p.period_error = 1;
    } else {
      s.every = k;
    }
  }
  if (s.every < 0) {
    hold_all(p);
    return;
  }
  // The period as it was, not as the thread says (PeriodTime): the detectors count this.
  const double nominal_s = static_cast<double>(period_ns) * 1e-9;
  const long long now_ns = rtapi_get_time();
  const auto period = lathectl::control::period_time(
      s.last_ns > 0 ? static_cast<double>(now_ns - s.last_ns) * 1e-9 : 0.0, nominal_s);
  s.last_ns = now_ns;
  if (*p.reset_max) timer.reset();
  if (*p.reset && !s.last_reset) {
    s.ctl.reset_alarm();
    s.overload_latched = false;
    s.breakage_latched = false;
    s.breakage.reset();
    s.tool_data_latched = s.tool_data_first = false;
  }
  s.last_reset = *p.reset;
  const double rpm_prog = *p.rpm_programmed;
  const double req_now = std::abs(*p.requested_vel);
  if (req_now == s.req_prev) s.req_stable = req_now;
  s.req_prev = req_now;
  {  // Under G95 motion.requested-vel is the F word for a straight feed but, for an arc, the
     // arc's velocity limit (80 mm/s in the sample config: profile_arcs.ngc's G2 read as
     // 80 mm/rev, the factor fell to 0.0006 and the arc crawled). motion.feed-upm is the move's
     // own F word times motion's net feed scale: the feed scale (halui.feed-override.value)
     // times the adaptive feed we wrote last period, which motion used in this one. halui's
     // value lags motion's scale by 0.1–0.2 s when the scale changes (above the programmed
     // feed), so the tag's F is off by up to the override's ratio then; it is used only where
     // requested-vel cannot be an F word (more than 4× the tag's: an arc's limit is ~500×).
    // Without halui's value (the sample config wires it only above the programmed feed,
    // lathectl-above.hal) motion's feed scale is taken as 1: an operator's override then
    // scales the tag's F too, which the 4× test below tolerates.
    const double net = (*p.scale_in_motion > 0.0 ? *p.scale_in_motion : 1.0) * *p.adaptive_feed;
    s.f_word = net > 1e-9 && *p.feed_upm > 0.0 ? *p.feed_upm / net : 0.0;
  }

  // Settings: checked every thread period, so a value motion puts out is in effect (or held as
  // bad) in the same period.
  OpSettings want = s.applied;
  double bad_value = 0.0;
  const SettingError err = resolve(s, p, want, bad_value);
  if (err != SettingError::None) {
    if (!s.bad) {
      *p.bad_line = *p.program_line;
      *p.bad_value = bad_value;
    }
    s.bad = true;
    *p.bad_code = static_cast<std::int32_t>(err);
  } else {
    s.bad = false;
    *p.bad_code = 0;
    if (!(want == s.applied)) {
      (void)s.ctl.set_operation(want.limit, want.feed_min, want.feed_max, want.mode == 2);
      s.applied = want;
    }
  }
  *p.bad_setting = s.bad;
  *p.limit = s.applied.limit;
  *p.feed_min_out = s.applied.feed_min;
  *p.feed_max_out = s.applied.feed_max;
  *p.adaptive_on = s.applied.mode == 2;
  const bool teach_mode = s.applied.mode == 3;
  const int tool = *p.tool_number;
  const int opn = static_cast<int>(std::isfinite(*p.op_cmd) ? *p.op_cmd : 0.0);
  if (teach_mode && (tool != s.teach_tool || opn != s.teach_op)) {  // one teach cut per key
    s.teach.start();
    s.teach_tool = tool;
    s.teach_op = opn;
  }
  if (!teach_mode) s.teach_tool = s.teach_op = -1;
  *p.teaching = teach_mode && s.teach.running();

  // One record per program line (or tool) with feed moves.
  const int line = *p.program_line;
  if (line != s.op_line || tool != s.op_tool) {
    publish_operation(s, p);
    s.op_line = line;
    s.op_tool = tool;
  }
  s.op_number = opn;
  s.op_mode = s.applied.mode;
  s.op_limit = s.applied.limit;

  {  // every servo period: the stop comes in the period the data changes
    const bool feed_move = *p.enable && (*p.motion_type == 2 || *p.motion_type == 3);
    if (s.tool_watch.update(tool, *p.tool_diameter, *p.tool_offset_x, *p.tool_offset_z, feed_move,
                            period.elapsed_s) &&
        !s.tool_data_latched) {
      s.tool_data_latched = true;
      s.tool_data_first = !(*p.alarm || s.breakage_latched || s.overload_latched);
    }
    *p.tool_data_changed = s.tool_data_latched;
    if (s.tool_data_latched) {
      *p.adaptive_feed = 0.0;
      *p.feed_hold = 1;
      *p.alarm = 1;
      if (s.tool_data_first)
        *p.alarm_reason = static_cast<std::int32_t>(lathectl::control::Reason::ToolDataChanged);
    }
  }
  if (s.stock) {  // every servo period: the stop comes in the period the load collapses
    lathectl::cutting::LathePlant::Input si;
    const bool homed = s.homed_gate(*p.homed, *p.x_pos, *p.z_pos);
    si.x_mm = homed ? *p.x_pos : std::nan("");
    si.z_mm = homed ? *p.z_pos : std::nan("");
    si.rpm = *p.rpm;
    lathectl::cutting::LathePlant::Output so;
    s.stock->step(si, period.elapsed_s, so);  // the spindle turned for the time that passed
    const double depth = so.in_contact ? so.depth_mm : 0.0;
    *p.predicted_depth = depth;
    const bool feed = *p.enable && (*p.motion_type == 2 || *p.motion_type == 3);
    const double load = s.power_sensor ? *p.load : *p.force;
    if (feed && s.applied.mode == 2 &&
        s.breakage.update(load, s.applied.limit, depth, period.elapsed_s) && !s.tool_data_latched)
      s.breakage_latched = true;
    if (!feed) s.breakage.reset();
    *p.breakage = s.breakage_latched;
    if (s.breakage_latched) {
      *p.adaptive_feed = 0.0;
      *p.feed_hold = 1;
      *p.alarm = 1;
      if (!(s.tool_data_latched && s.tool_data_first))
        *p.alarm_reason = static_cast<std::int32_t>(lathectl::control::Reason::ToolBreakage);
    }
  }
  if (s.count++ % s.every == 0) {
    timer.start();
    const double dt = s.ctl.params().period_s;
    // The control period as measured (every `every` thread periods): the detectors' time.
    const auto ctl_period = lathectl::control::period_time(
        s.last_ctl_ns > 0 ? static_cast<double>(now_ns - s.last_ctl_ns) * 1e-9 : 0.0, dt);
    s.last_ctl_ns = now_ns;
    const bool enabled = *p.enable;
    const double rpm = std::abs(*p.rpm);
    const bool feed_block = enabled && (*p.motion_type == 2 || *p.motion_type == 3);
    lathectl::control::AdaptiveSignals sig;
    sig.force = *p.force;
    sig.spindle_power_W = *p.spindle_power;
    sig.idle_power_W = lathectl::drives::idle_power_W(s.spindle, rpm);
    auto parameter = s.parameter;
    bool sensing = true;
    if (s.power_sensor) {
      // Outside feed moves (rapids, dwells, tool changes) the drive draws its idle power only.
      s.tare.update(rpm, *p.spindle_power, dt, !feed_block);
      const double idle = s.tare.idle_W(rpm);
      *p.idle_power = std::isfinite(idle) ? idle : 0.0;
      const auto k = s.tare.coefficients();
      for (int i = 0; i < 3; ++i) *p.idle_p[i] = k[static_cast<std::size_t>(i)];
      sensing = s.tare.covers(rpm);
      sig.force = (*p.spindle_power - idle) * s.spindle.efficiency;
      // Outside feed moves nothing is cut: what is left is the power that accelerates or brakes
      // the spindle (M3/M5, speed changes), not a load.
      if (!feed_block) sig.force = std::max(sig.force, 0.0);
      sig.spindle_power_W = *p.spindle_power;
      sig.idle_power_W = idle;
      parameter = lathectl::cutting::ForceParameter::Power;
      if (!sensing) sig.force = 0.0;  // nothing known yet: the program's feed (below)
    }
    *p.tare_ready = sensing;
    sig.rpm = rpm;
    sig.feed_rate_mm_per_min = std::abs(*p.current_vel) * 60.0;
    // Sensor 20: a measured cutting speed when one is wired, else π·D·n at the tool's diameter.
    const double v_meas = *p.cutting_speed;
    sig.speed_m_per_min =
        v_meas > 0.0 ? v_meas : 3.14159265358979323846 * 2.0 * std::abs(*p.x_pos) * rpm / 1000.0;
    sig.feed_block = feed_block;
    auto in = lathectl::control::adaptive_input(parameter, sig);
    in.dt_s = ctl_period.elapsed_s;
    (void)s.ctl.update(in, s.out);
    *p.cut_power = in.cut_power_W;
    *p.load = sig.force;
    const auto& o = s.out;

    // Contact (the controller's own in_cut runs only while it regulates): the load above the
    // air threshold, left after the air time.
    const auto& cp = s.ctl.params();
    if (feed_block && std::isfinite(sig.force) && sig.force > cp.air_threshold * s.applied.limit) {
      s.contact = true;
      s.below_air_s = 0.0;
    } else if (s.contact) {
      s.below_air_s += dt;
      if (!feed_block || s.below_air_s >= cp.air_time_s) s.contact = false;
    }
    // The load's mean over the last whole revolution (overload levels, the panel).
    if (s.contact && rpm > 0.0 && std::isfinite(sig.force)) {
      s.rev_sum += sig.force;
      s.rev_n += 1.0;
      s.rev_phase += ctl_period.elapsed_s * rpm / 60.0;  // the spindle turns in real time
      if (s.rev_phase >= 1.0) {
        s.load_rev = s.rev_sum / s.rev_n;
        s.rev_phase -= 1.0;
        s.rev_sum = s.rev_n = 0.0;
      }
    } else {
      s.rev_phase = s.rev_sum = s.rev_n = 0.0;
      if (!s.contact) s.load_rev = 0.0;
    }
    *p.load_rev = s.load_rev;
    *p.load_pct = s.applied.limit > 0.0 ? 100.0 * s.load_rev / s.applied.limit : 0.0;
    // AFC's overload levels, percentages of the reference (taught, else the limit).
    const auto* tl = tool_of(s, tool);
    const double ref = s.applied.reference;
    *p.overload_warn =
        tl != nullptr && tl->warn_pct > 0.0 && s.load_rev > tl->warn_pct / 100.0 * ref;
    if (tl != nullptr && tl->hold_pct > 0.0 && s.load_rev > tl->hold_pct / 100.0 * ref)
      s.overload_latched = true;
    *p.overload_hold = s.overload_latched;

    // Teach-in: the program's feed; the reference when the cut has ended.
    if (teach_mode && s.teach.sample(sig.force, rpm, dt, s.contact)) {
      auto* t = taught_of(s, s.teach_tool, s.teach_op);
      if (t == nullptr && s.n_taught < kMaxTaught) t = &s.taught[s.n_taught++];
      if (t != nullptr) *t = {s.teach_tool, s.teach_op, s.teach.reference()};
      *p.teach_tool = s.teach_tool;
      *p.teach_op = s.teach_op;
      *p.teach_ref = s.teach.reference();
      *p.teach_seq = *p.teach_seq + 1;
    }

    double factor = 1.0;
    const bool regulating = s.applied.mode == 2 && sensing;
    const double max_ovr = *p.max_override;
    if (feed_block && regulating) {
      // The program's feed per revolution: motion reports the F word itself under G95, a
      // velocity [mm/s] under G94 (motion.requested-vel: without the feed scale).
      const double req = s.req_stable;
      const double prog_per_rev = *p.per_rev
                                      ? (s.f_word > 0.0 && req > 4.0 * s.f_word ? s.f_word : req)
                                  : rpm > 0.0 ? req * 60.0 / rpm
                                              : 0.0;
      // Above the program's feed up to the machine's maximum override (split_feed_override).
      factor = o.feed_hold ? 0.0
               : prog_per_rev > 0.0
                   ? std::clamp(o.feed_per_rev_mm / prog_per_rev, 0.0, std::max(max_ovr, 1.0))
                   : 1.0;
    }
    const bool hold = enabled && (o.feed_hold || s.bad || s.overload_latched ||
                                  s.breakage_latched || s.tool_data_latched);
    // The operator's knob times the factor; the ceiling to halui, every decrease on
    // adaptive-feed. Not enabled: the knob alone, on feed moves as before.
    const auto fo = lathectl::control::split_feed_override(factor, *p.knob, max_ovr, kOverrideStep,
                                                           *p.feed_override, *p.scale_in_motion,
                                                           enabled && feed_block);
    *p.feed_override = fo.scale;
    s.scale_mismatch_s = std::abs(*p.scale_in_motion - fo.scale) > 0.5 * kOverrideStep
                             ? s.scale_mismatch_s + dt
                             : 0.0;
    if (s.scale_mismatch_s > kRescaleAfter) {
      s.rescale_s = kRescaleFor;
      s.scale_mismatch_s = 0.0;
    }
    // (one count lower while re-sending: below the divisor, so the feed only ever dips by it)
    *p.feed_override_counts = static_cast<std::int32_t>(std::lround(fo.scale / kOverrideStep)) -
                              (s.rescale_s > 0.0 ? 1 : 0);
    s.rescale_s = std::max(s.rescale_s - dt, 0.0);
    *p.feed_factor = hold ? 0.0 : fo.net;
    *p.adaptive_feed = hold ? 0.0 : fo.adaptive;
    *p.feed_hold = hold;
    *p.alarm = o.alarm || s.overload_latched || s.breakage_latched || s.tool_data_latched;
    *p.reason = static_cast<std::int32_t>(o.reason);
    *p.alarm_reason = s.tool_data_latched && s.tool_data_first
                          ? static_cast<std::int32_t>(lathectl::control::Reason::ToolDataChanged)
                      : s.breakage_latched && !o.alarm
                          ? static_cast<std::int32_t>(lathectl::control::Reason::ToolBreakage)
                          : static_cast<std::int32_t>(o.alarm_reason);
    *p.feed_per_rev = o.feed_per_rev_mm;
    *p.speed_cmd = o.speed_m_per_min;
    *p.speed_opt = o.speed_opt_m_per_min;
    *p.in_cut = o.in_cut;
    s.stats.sample(sig.force, *p.feed_factor, rpm, dt, s.contact);
    if (feed_block) s.op_feed_s += dt;
    if (feed_block && s.contact) {
      const auto r = static_cast<unsigned>(o.reason);
      if (r < 31) s.op_reasons |= static_cast<std::int32_t>(1u << r);
      if (*p.alarm && s.op_alarm == 0) s.op_alarm = *p.alarm_reason;  // any latched alarm
    }
    // Seed 004's speed law drives the spindle while the program runs it; otherwise the program's
    // speed passes through.
    double rpm_out = rpm_prog;
    if (enabled && s.speed_law && regulating && rpm_prog != 0.0)
      rpm_out = std::copysign(o.rpm, rpm_prog);
    *p.spindle_speed_out = rpm_out;
    *p.spindle_override = rpm_prog != 0.0 ? rpm_out / rpm_prog : 1.0;
    *p.update_ns = timer.stop();
  } else {
    if (!(*p.enable && s.speed_law && s.applied.mode == 2))
      *p.spindle_speed_out = rpm_prog;  // pass program speed changes through between updates
    if (s.bad || s.breakage_latched || s.tool_data_latched) {  // held in the period it appears
      *p.adaptive_feed = 0.0;
      *p.feed_hold = 1;
    }
  }
  *p.update_ns_max = timer.max();
}

std::string read_text(const char* path, const char* what) {
  lathectl::hal::require_readable(path, what);
  return lathectl::io::read_scenario_text(path);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  comp_id = hal_init(kName);
  if (comp_id < 0) return comp_id;
  return lathectl::hal::guarded_load(kName, comp_id, [] {
    using lathectl::hal::param;
    using lathectl::hal::pin;
    namespace e_adaptive = lathectl::systems::e_adaptive;
    const auto sc = lathectl::hal::load_system(scenario, e_adaptive::kReadSection);
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    auto state = std::make_unique<State>();
    const std::string sensor_kind = sensor != nullptr && *sensor != '\0' ? sensor : "force";
    if (sensor_kind != "force" && sensor_kind != "power")
      throw lathectl::hal::Error("module parameter sensor=" + sensor_kind +
                                 ": expected force or power");
    state->power_sensor = sensor_kind == "power";
    auto c = e.controller;
    if (state->power_sensor) {  // the sensor's valid range in W (the scenario's is its sensor's)
      c.sensor_monitor.min = -0.2 * e.spindle.max_power_W;
      c.sensor_monitor.max = 2.0 * e.spindle.max_power_W;
      // The default limit in W (the scenario's is in its sensor's unit): the power the spindle
      // has for cutting, the speed law's clamp.
      c.force_limit = std::min(c.cut_power_max_W, e.spindle.max_power_W);
    }
    if (z_origin_mm != nullptr && *z_origin_mm != '\0') {
      // The path-aware detector replaces the controller's collapse detector (its spike stays).
      lathectl::cutting::LathePlant::Params sp;
      sp.z_origin_mm = lathectl::hal::number_param(z_origin_mm, "z_origin_mm", 0.0);
      state->stock = std::make_unique<lathectl::cutting::LathePlant>();
      state->stock->configure(e, sp);
      lathectl::control::PathBreakage::Params bp;
      bp.window_s = c.breakage_drop_window_s;
      bp.air = c.air_threshold;
      state->breakage.configure(bp);
      c.breakage_drop_window_s = 0.0;
    }
    state->ctl.configure(c);
    state->base = c;
    state->parameter = e.force_parameter;
    state->spindle = e.spindle;
    state->speed_law = e.controller.mode == AdaptiveFeedController::Mode::ForceFeedSpeed;
    // The rating a program's value may not exceed: the tool table's, else what the sensor can
    // measure (the dynamometer's range; with sensor=power, the spindle's power).
    state->rating.limit_max = state->power_sensor ? e.spindle.max_power_W
                              : e.force_parameter == lathectl::cutting::ForceParameter::Power
                                  ? e.spindle.max_power_W
                                  : e.force_sensor.range;
    state->rating.feed_max_mm_per_rev = c.feed_max_mm_per_rev;
    if (tools != nullptr && *tools != '\0') {
      const auto t = lathectl::hal::read_tool_table(read_text(tools, "tool limits"), tools);
      if (t.limit_max > 0.0) state->rating.limit_max = t.limit_max;
      if (t.feed_max_mm_per_rev > 0.0) state->rating.feed_max_mm_per_rev = t.feed_max_mm_per_rev;
      if (t.tools.size() > kMaxTools)
        throw lathectl::hal::Error(std::string(tools) + ": more than " + std::to_string(kMaxTools) +
                                   " tools");
      for (const auto& l : t.tools) state->tools[state->n_tools++] = l;
    }
    const char* unit = state->power_sensor ? "W" : "N";
    if (taught != nullptr && *taught != '\0') {
      std::FILE* f = std::fopen(taught, "r");  // absent: nothing taught yet
      if (f != nullptr) {
        std::fclose(f);
        for (const auto& t : lathectl::hal::read_taught(read_text(taught, "taught"), taught)) {
          if (t.unit != unit)
            throw lathectl::hal::Error(std::string(taught) + ": tool " + std::to_string(t.tool) +
                                       " was taught in " + t.unit + ", this sensor measures " +
                                       unit);
          if (state->n_taught >= kMaxTaught)
            throw lathectl::hal::Error(std::string(taught) + ": more than " +
                                       std::to_string(kMaxTaught) + " references");
          state->taught[state->n_taught++] = {t.tool, t.operation, t.reference};
        }
      }
    }
    lathectl::control::IdleTare::Params tp;
    tp.rpm_max = e.spindle.max_rpm;
    tp.rpm_min = e.spindle.min_rpm;
    state->tare.configure(tp);
    state->applied = {c.force_limit, c.feed_min_mm_per_rev, c.feed_max_mm_per_rev, 2,
                      c.force_limit};
    pins = lathectl::hal::allocate_pins<Pins>();
    Pins& p = *pins;
    pin(&p.force, HAL_IN, comp_id, kPrefix, "force");
    pin(&p.rpm, HAL_IN, comp_id, kPrefix, "spindle-rpm");
    pin(&p.rpm_programmed, HAL_IN, comp_id, kPrefix, "spindle-rpm-programmed");
    pin(&p.current_vel, HAL_IN, comp_id, kPrefix, "current-vel");
    pin(&p.requested_vel, HAL_IN, comp_id, kPrefix, "requested-vel");
    pin(&p.feed_upm, HAL_IN, comp_id, kPrefix, "feed-upm");
    pin(&p.motion_type, HAL_IN, comp_id, kPrefix, "motion-type");
    pin(&p.x_pos, HAL_IN, comp_id, kPrefix, "x-pos");
    pin(&p.cutting_speed, HAL_IN, comp_id, kPrefix, "cutting-speed");
    pin(&p.spindle_power, HAL_IN, comp_id, kPrefix, "spindle-power");
    pin(&p.per_rev, HAL_IN, comp_id, kPrefix, "feed-per-rev-mode");
    pin(&p.enable, HAL_IN, comp_id, kPrefix, "enable");
    pin(&p.reset, HAL_IN, comp_id, kPrefix, "reset");
    pin(&p.limit_cmd, HAL_IN, comp_id, kPrefix, "limit-cmd");
    pin(&p.feed_min_cmd, HAL_IN, comp_id, kPrefix, "feed-min-cmd");
    pin(&p.feed_max_cmd, HAL_IN, comp_id, kPrefix, "feed-max-cmd");
    pin(&p.mode_cmd, HAL_IN, comp_id, kPrefix, "mode-cmd");
    pin(&p.op_cmd, HAL_IN, comp_id, kPrefix, "operation-cmd");
    pin(&p.tool_number, HAL_IN, comp_id, kPrefix, "tool-number");
    pin(&p.program_line, HAL_IN, comp_id, kPrefix, "program-line");
    pin(&p.z_pos, HAL_IN, comp_id, kPrefix, "z-pos");
    pin(&p.homed, HAL_IN, comp_id, kPrefix, "homed");
    pin(&p.knob, HAL_IN, comp_id, kPrefix, "operator-override");
    pin(&p.max_override, HAL_IN, comp_id, kPrefix, "max-feed-override");
    pin(&p.scale_in_motion, HAL_IN, comp_id, kPrefix, "feed-override-in-motion");
    pin(&p.adaptive_feed, HAL_OUT, comp_id, kPrefix, "adaptive-feed");
    pin(&p.feed_override, HAL_OUT, comp_id, kPrefix, "feed-override");
    pin(&p.feed_override_counts, HAL_OUT, comp_id, kPrefix, "feed-override-counts");
    pin(&p.feed_factor, HAL_OUT, comp_id, kPrefix, "feed-factor");
    pin(&p.spindle_speed_out, HAL_OUT, comp_id, kPrefix, "spindle-speed-out");
    pin(&p.spindle_override, HAL_OUT, comp_id, kPrefix, "spindle-override");
    pin(&p.feed_hold, HAL_OUT, comp_id, kPrefix, "feed-hold");
    pin(&p.alarm, HAL_OUT, comp_id, kPrefix, "alarm");
    pin(&p.reason, HAL_OUT, comp_id, kPrefix, "reason");
    pin(&p.alarm_reason, HAL_OUT, comp_id, kPrefix, "alarm-reason");
    pin(&p.feed_per_rev, HAL_OUT, comp_id, kPrefix, "feed-per-rev");
    pin(&p.speed_cmd, HAL_OUT, comp_id, kPrefix, "cutting-speed-cmd");
    pin(&p.speed_opt, HAL_OUT, comp_id, kPrefix, "cutting-speed-opt");
    pin(&p.cut_power, HAL_OUT, comp_id, kPrefix, "cut-power");
    pin(&p.in_cut, HAL_OUT, comp_id, kPrefix, "in-cut");
    pin(&p.period_error, HAL_OUT, comp_id, kPrefix, "period-error");
    pin(&p.update_ns, HAL_OUT, comp_id, kPrefix, "update-ns");
    pin(&p.update_ns_max, HAL_OUT, comp_id, kPrefix, "update-ns-max");
    pin(&p.reset_max, HAL_IN, comp_id, kPrefix, "reset-max");
    pin(&p.load, HAL_OUT, comp_id, kPrefix, "load");
    pin(&p.limit, HAL_OUT, comp_id, kPrefix, "limit");
    pin(&p.feed_min_out, HAL_OUT, comp_id, kPrefix, "feed-min");
    pin(&p.feed_max_out, HAL_OUT, comp_id, kPrefix, "feed-max");
    pin(&p.adaptive_on, HAL_OUT, comp_id, kPrefix, "adaptive-on");
    pin(&p.teaching, HAL_OUT, comp_id, kPrefix, "teaching");
    pin(&p.idle_power, HAL_OUT, comp_id, kPrefix, "idle-power");
    pin(&p.tare_ready, HAL_OUT, comp_id, kPrefix, "tare-ready");
    pin(&p.idle_p[0], HAL_OUT, comp_id, kPrefix, "idle-p0");
    pin(&p.idle_p[1], HAL_OUT, comp_id, kPrefix, "idle-p1");
    pin(&p.idle_p[2], HAL_OUT, comp_id, kPrefix, "idle-p2");
    pin(&p.bad_setting, HAL_OUT, comp_id, kPrefix, "bad-setting");
    pin(&p.bad_code, HAL_OUT, comp_id, kPrefix, "bad-code");
    pin(&p.bad_line, HAL_OUT, comp_id, kPrefix, "bad-line");
    pin(&p.bad_value, HAL_OUT, comp_id, kPrefix, "bad-value");
    pin(&p.overload_warn, HAL_OUT, comp_id, kPrefix, "overload-warn");
    pin(&p.overload_hold, HAL_OUT, comp_id, kPrefix, "overload-hold");
    pin(&p.load_rev, HAL_OUT, comp_id, kPrefix, "load-rev");
    pin(&p.load_pct, HAL_OUT, comp_id, kPrefix, "load-percent");
    pin(&p.predicted_depth, HAL_OUT, comp_id, kPrefix, "predicted-depth");
    pin(&p.breakage, HAL_OUT, comp_id, kPrefix, "breakage");
    pin(&p.tool_diameter, HAL_IN, comp_id, kPrefix, "tool-diameter");
    pin(&p.tool_offset_x, HAL_IN, comp_id, kPrefix, "tool-offset-x");
    pin(&p.tool_offset_z, HAL_IN, comp_id, kPrefix, "tool-offset-z");
    pin(&p.tool_data_changed, HAL_OUT, comp_id, kPrefix, "tool-data-changed");
    pin(&p.op_seq, HAL_OUT, comp_id, kPrefix, "op-seq");
    pin(&p.op_line, HAL_OUT, comp_id, kPrefix, "op-line");
    pin(&p.op_tool, HAL_OUT, comp_id, kPrefix, "op-tool");
    pin(&p.op_number, HAL_OUT, comp_id, kPrefix, "op-operation");
    pin(&p.op_mode, HAL_OUT, comp_id, kPrefix, "op-mode");
    pin(&p.op_limit, HAL_OUT, comp_id, kPrefix, "op-limit");
    pin(&p.op_mean, HAL_OUT, comp_id, kPrefix, "op-load-mean");
    pin(&p.op_peak, HAL_OUT, comp_id, kPrefix, "op-load-peak");
    pin(&p.op_feed_min, HAL_OUT, comp_id, kPrefix, "op-feed-min");
    pin(&p.op_feed_mean, HAL_OUT, comp_id, kPrefix, "op-feed-mean");
    pin(&p.op_time_cut, HAL_OUT, comp_id, kPrefix, "op-time-in-cut");
    pin(&p.op_time, HAL_OUT, comp_id, kPrefix, "op-time");
    pin(&p.op_reasons, HAL_OUT, comp_id, kPrefix, "op-reasons");
    pin(&p.op_alarm, HAL_OUT, comp_id, kPrefix, "op-alarm");
    pin(&p.teach_seq, HAL_OUT, comp_id, kPrefix, "teach-seq");
    pin(&p.teach_tool, HAL_OUT, comp_id, kPrefix, "teach-tool");
    pin(&p.teach_op, HAL_OUT, comp_id, kPrefix, "teach-operation");
    pin(&p.teach_ref, HAL_OUT, comp_id, kPrefix, "teach-reference");
    *p.adaptive_feed = 1.0;
    *p.knob = 1.0;
    *p.max_override = 1.0;
    *p.feed_override = 1.0;
    *p.feed_override_counts = 1000;
    *p.feed_factor = 1.0;
    *p.spindle_override = 1.0;
    *p.program_line = -1;
    param(&p.force_limit, HAL_RO, comp_id, kPrefix, "force-limit", c.force_limit);
    param(&p.feed_min, HAL_RO, comp_id, kPrefix, "feed-min-default", c.feed_min_mm_per_rev);
    param(&p.feed_max, HAL_RO, comp_id, kPrefix, "feed-max-default", c.feed_max_mm_per_rev);
    param(&p.feed_programmed, HAL_RO, comp_id, kPrefix, "feed-programmed",
          c.feed_programmed_mm_per_rev);
    param(&p.speed_programmed, HAL_RO, comp_id, kPrefix, "cutting-speed-programmed",
          c.speed_programmed_m_per_min);
    param(&p.control_period, HAL_RO, comp_id, kPrefix, "control-period", c.period_s);
    param(&p.rating, HAL_RO, comp_id, kPrefix, "rating", state->rating.limit_max);
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
