// lathectl_adaptive — system E's machine side (seed 004: force held by the feed, cutting speed by
// V_opt = V_p·(S_p/S_cur)^y_v, and what a shop runs around it) as a realtime HAL component. The
// machine side is control::AdaptiveMachine, the object `lathectl run` and `lathectl optimize` run
// too; this file only maps HAL pins to its Input and Output and reads the files at load.
//
//   loadrt lathectl_adaptive scenario=PATH [tools=PATH] [taught=PATH] [sensor=force|power]
//                            [z_origin_mm=Z]
//   addf lathectl-adaptive servo-thread
//
// The controller's settings come from the scenario's [controller] and [sensor] sections (the
// same file `lathectl run` reads); the per-tool limits and taught references from the tools= and
// taught= files (systems/e_adaptive/tool_limits.hpp). Per-operation settings come from motion's
// analog outputs (M68 E0..E4). The period the latching detectors count is measured here
// (rtapi_get_time()), not the thread's nominal one. Pins, parameters and units:
// lathectl_adaptive(9).

#include <algorithm>
#include <cstdio>
#include <memory>

#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl_hal.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/e_adaptive/tool_limits.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-E adaptive feed and cutting-speed controller for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(
    scenario, "system-E scenario file (TOML) whose [controller] and [sensor] set the controller");
LATHECTL_HAL_PARAM(tools,
                   "per-tool limits table (TOML, optional): rating, defaults, overload levels");
LATHECTL_HAL_PARAM(taught, "teach-in references (TOML written by lathectl_oplog; absent: none)");
LATHECTL_HAL_PARAM(z_origin_mm,
                   "machine z of the stock's face: turns on the stock model for the "
                   "path-aware breakage detector (unset: the controller's own)");
LATHECTL_HAL_PARAM(sensor,
                   "force (the scenario's sensor, default) or power (spindle-power - idle)");

namespace {

constexpr const char* kName = "lathectl_adaptive";
constexpr const char* kPrefix = "lathectl-adaptive";

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
  hal_float_t* depth_ahead;      // the stock model's depth ahead of the tool [mm]
  hal_float_t* feed_ceiling;     // feed-forward's ceiling [mm/rev] (0: none)
  hal_float_t* specific_force;   // κ, measured load over the handbook law's
  hal_float_t* inertia;          // the spindle inertia in use [kg·m²] (learned or given)
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

using lathectl::control::AdaptiveMachine;

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<AdaptiveMachine> machine;
AdaptiveMachine::Output out;
lathectl::hal::HomedGate homed_gate;
lathectl::hal::UpdateTimer timer;
long long last_ns = 0;

void update(void*, long period_ns) {
  Pins& p = *pins;
  const long long now_ns = rtapi_get_time();
  AdaptiveMachine::Input in;
  in.nominal_period_s = static_cast<double>(period_ns) * 1e-9;
  in.elapsed_s = last_ns > 0 ? static_cast<double>(now_ns - last_ns) * 1e-9 : 0.0;
  last_ns = now_ns;
  in.enable = *p.enable;
  in.reset = *p.reset;
  in.force = *p.force;
  in.spindle_power_W = *p.spindle_power;
  in.rpm = *p.rpm;
  in.rpm_programmed = *p.rpm_programmed;
  in.current_vel_mm_s = *p.current_vel;
  in.requested_vel = *p.requested_vel;
  in.feed_upm = *p.feed_upm;
  in.motion_type = *p.motion_type;
  in.per_rev = *p.per_rev;
  in.homed = homed_gate(*p.homed, *p.x_pos, *p.z_pos);
  in.x_mm = *p.x_pos;
  in.z_mm = *p.z_pos;
  in.cutting_speed_m_per_min = *p.cutting_speed;
  in.limit_cmd = *p.limit_cmd;
  in.feed_min_cmd = *p.feed_min_cmd;
  in.feed_max_cmd = *p.feed_max_cmd;
  in.mode_cmd = *p.mode_cmd;
  in.operation_cmd = *p.op_cmd;
  in.tool_number = *p.tool_number;
  in.program_line = *p.program_line;
  in.tool_diameter = *p.tool_diameter;
  in.tool_offset_x = *p.tool_offset_x;
  in.tool_offset_z = *p.tool_offset_z;
  in.knob = *p.knob;
  in.max_override = *p.max_override;
  in.scale_in_motion = *p.scale_in_motion;
  if (*p.reset_max) timer.reset();
  timer.start();
  machine->update(in, out);
  const std::int32_t ns = timer.stop();
  if (out.control_period) *p.update_ns = ns;
  *p.update_ns_max = timer.max();

  *p.adaptive_feed = out.adaptive_feed;
  *p.feed_override = out.feed_override;
  *p.feed_override_counts = out.feed_override_counts;
  *p.feed_factor = out.feed_factor;
  *p.spindle_speed_out = out.spindle_speed_out;
  *p.spindle_override = out.spindle_override;
  *p.feed_hold = out.feed_hold;
  *p.alarm = out.alarm;
  *p.reason = static_cast<std::int32_t>(out.reason);
  *p.alarm_reason = static_cast<std::int32_t>(out.alarm_reason);
  *p.feed_per_rev = out.feed_per_rev_mm;
  *p.speed_cmd = out.speed_cmd_m_per_min;
  *p.speed_opt = out.speed_opt_m_per_min;
  *p.cut_power = out.cut_power_W;
  *p.in_cut = out.in_cut;
  *p.period_error = out.period_error;
  *p.load = out.load;
  *p.limit = out.limit;
  *p.feed_min_out = out.feed_min;
  *p.feed_max_out = out.feed_max;
  *p.adaptive_on = out.adaptive_on;
  *p.teaching = out.teaching;
  *p.idle_power = out.idle_power_W;
  *p.tare_ready = out.tare_ready;
  for (std::size_t i = 0; i < 3; ++i) *p.idle_p[i] = out.idle_law[i];
  *p.bad_setting = out.bad_setting;
  *p.bad_code = static_cast<std::int32_t>(out.bad_code);
  *p.bad_line = out.bad_line;
  *p.bad_value = out.bad_value;
  *p.overload_warn = out.overload_warn;
  *p.overload_hold = out.overload_hold;
  *p.load_rev = out.load_rev;
  *p.load_pct = out.load_percent;
  *p.predicted_depth = out.predicted_depth_mm;
  *p.depth_ahead = out.depth_ahead_mm;
  *p.feed_ceiling = out.feed_ceiling_mm_per_rev;
  *p.specific_force = out.specific_force_ratio;
  *p.inertia = out.inertia_kg_m2;
  *p.breakage = out.breakage;
  *p.tool_data_changed = out.tool_data_changed;
  if (out.op.seq != *p.op_seq) {  // a record: its fields first, op-seq last
    *p.op_line = out.op.line;
    *p.op_tool = out.op.tool;
    *p.op_number = out.op.operation;
    *p.op_mode = out.op.mode;
    *p.op_limit = out.op.limit;
    *p.op_mean = out.op.load_mean;
    *p.op_peak = out.op.load_peak;
    *p.op_feed_min = out.op.feed_min;
    *p.op_feed_mean = out.op.feed_mean;
    *p.op_time_cut = out.op.time_in_cut_s;
    *p.op_time = out.op.time_s;
    *p.op_reasons = static_cast<std::int32_t>(out.op.reasons);
    *p.op_alarm = out.op.alarm;
    *p.op_seq = out.op.seq;
  }
  if (out.teach.seq != *p.teach_seq) {
    *p.teach_tool = out.teach.tool;
    *p.teach_op = out.teach.operation;
    *p.teach_ref = out.teach.reference;
    *p.teach_seq = out.teach.seq;
  }
}

std::string read_text(const char* path, const char* what) {
  lathectl::hal::require_readable(path, what);
  return lathectl::io::read_scenario_text(path);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    namespace e_adaptive = lathectl::systems::e_adaptive;
    const auto sc = lathectl::hal::load_system(scenario, e_adaptive::kReadSection);
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    // What this host adds to the scenario (module parameters and files); the parameters
    // themselves are derived where every host derives them (e_adaptive::machine_params).
    e_adaptive::MachineHost host;
    const std::string sensor_kind = sensor != nullptr && *sensor != '\0' ? sensor : "force";
    if (sensor_kind != "force" && sensor_kind != "power")
      throw lathectl::hal::Error("module parameter sensor=" + sensor_kind +
                                 ": expected force or power");
    if (sensor_kind == "power") host.load = e_adaptive::MachineHost::Load::SpindlePower;
    host.z_origin_mm = z_origin_mm != nullptr && *z_origin_mm != '\0'
                           ? lathectl::hal::number_param(z_origin_mm, "z_origin_mm", 0.0)
                           : std::nan("");
    e_adaptive::ToolTable table;
    if (tools != nullptr && *tools != '\0') {
      table = e_adaptive::read_tool_table(read_text(tools, "tool limits"), tools);
      host.tools = &table;
      host.tools_file = tools;
    }
    if (taught != nullptr && *taught != '\0') {
      std::FILE* f = std::fopen(taught, "r");  // absent: nothing taught yet
      if (f != nullptr) {
        std::fclose(f);
        host.taught = e_adaptive::read_taught(read_text(taught, "taught"), taught);
        host.taught_file = taught;
      }
    }
    AdaptiveMachine::Params mp;
    try {
      mp = e_adaptive::machine_params(e, host);
    } catch (const std::invalid_argument& x) {
      throw lathectl::hal::Error(x.what());
    }
    const auto& c = mp.controller;
    auto m = std::make_unique<AdaptiveMachine>();
    m->configure(mp);
    pins = lathectl::hal::allocate_pins<Pins>();
    const lathectl::hal::Exporter x(comp_id, kPrefix);
    Pins& p = *pins;
    x.in(&p.force, "force");
    x.in(&p.rpm, "spindle-rpm");
    x.in(&p.rpm_programmed, "spindle-rpm-programmed");
    x.in(&p.current_vel, "current-vel");
    x.in(&p.requested_vel, "requested-vel");
    x.in(&p.feed_upm, "feed-upm");
    x.in(&p.motion_type, "motion-type");
    x.in(&p.x_pos, "x-pos");
    x.in(&p.cutting_speed, "cutting-speed");
    x.in(&p.spindle_power, "spindle-power");
    x.in(&p.per_rev, "feed-per-rev-mode");
    x.in(&p.enable, "enable");
    x.in(&p.reset, "reset");
    x.in(&p.limit_cmd, "limit-cmd");
    x.in(&p.feed_min_cmd, "feed-min-cmd");
    x.in(&p.feed_max_cmd, "feed-max-cmd");
    x.in(&p.mode_cmd, "mode-cmd");
    x.in(&p.op_cmd, "operation-cmd");
    x.in(&p.tool_number, "tool-number");
    x.in(&p.program_line, "program-line");
    x.in(&p.z_pos, "z-pos");
    x.in(&p.homed, "homed");
    x.in(&p.knob, "operator-override");
    x.in(&p.max_override, "max-feed-override");
    x.in(&p.scale_in_motion, "feed-override-in-motion");
    x.out(&p.adaptive_feed, "adaptive-feed");
    x.out(&p.feed_override, "feed-override");
    x.out(&p.feed_override_counts, "feed-override-counts");
    x.out(&p.feed_factor, "feed-factor");
    x.out(&p.spindle_speed_out, "spindle-speed-out");
    x.out(&p.spindle_override, "spindle-override");
    x.out(&p.feed_hold, "feed-hold");
    x.out(&p.alarm, "alarm");
    x.out(&p.reason, "reason");
    x.out(&p.alarm_reason, "alarm-reason");
    x.out(&p.feed_per_rev, "feed-per-rev");
    x.out(&p.speed_cmd, "cutting-speed-cmd");
    x.out(&p.speed_opt, "cutting-speed-opt");
    x.out(&p.cut_power, "cut-power");
    x.out(&p.in_cut, "in-cut");
    x.out(&p.period_error, "period-error");
    x.out(&p.update_ns, "update-ns");
    x.out(&p.update_ns_max, "update-ns-max");
    x.in(&p.reset_max, "reset-max");
    x.out(&p.load, "load");
    x.out(&p.limit, "limit");
    x.out(&p.feed_min_out, "feed-min");
    x.out(&p.feed_max_out, "feed-max");
    x.out(&p.adaptive_on, "adaptive-on");
    x.out(&p.teaching, "teaching");
    x.out(&p.idle_power, "idle-power");
    x.out(&p.tare_ready, "tare-ready");
    x.out(&p.idle_p[0], "idle-p0");
    x.out(&p.idle_p[1], "idle-p1");
    x.out(&p.idle_p[2], "idle-p2");
    x.out(&p.bad_setting, "bad-setting");
    x.out(&p.bad_code, "bad-code");
    x.out(&p.bad_line, "bad-line");
    x.out(&p.bad_value, "bad-value");
    x.out(&p.overload_warn, "overload-warn");
    x.out(&p.overload_hold, "overload-hold");
    x.out(&p.load_rev, "load-rev");
    x.out(&p.load_pct, "load-percent");
    x.out(&p.predicted_depth, "predicted-depth");
    x.out(&p.depth_ahead, "depth-ahead");
    x.out(&p.feed_ceiling, "feed-ceiling");
    x.out(&p.specific_force, "specific-force");
    x.out(&p.inertia, "inertia");
    x.out(&p.breakage, "breakage");
    x.in(&p.tool_diameter, "tool-diameter");
    x.in(&p.tool_offset_x, "tool-offset-x");
    x.in(&p.tool_offset_z, "tool-offset-z");
    x.out(&p.tool_data_changed, "tool-data-changed");
    x.out(&p.op_seq, "op-seq");
    x.out(&p.op_line, "op-line");
    x.out(&p.op_tool, "op-tool");
    x.out(&p.op_number, "op-operation");
    x.out(&p.op_mode, "op-mode");
    x.out(&p.op_limit, "op-limit");
    x.out(&p.op_mean, "op-load-mean");
    x.out(&p.op_peak, "op-load-peak");
    x.out(&p.op_feed_min, "op-feed-min");
    x.out(&p.op_feed_mean, "op-feed-mean");
    x.out(&p.op_time_cut, "op-time-in-cut");
    x.out(&p.op_time, "op-time");
    x.out(&p.op_reasons, "op-reasons");
    x.out(&p.op_alarm, "op-alarm");
    x.out(&p.teach_seq, "teach-seq");
    x.out(&p.teach_tool, "teach-tool");
    x.out(&p.teach_op, "teach-operation");
    x.out(&p.teach_ref, "teach-reference");
    *p.adaptive_feed = 1.0;
    *p.knob = 1.0;
    *p.max_override = 1.0;
    *p.feed_override = 1.0;
    *p.feed_override_counts = 1000;
    *p.feed_factor = 1.0;
    *p.spindle_override = 1.0;
    *p.program_line = -1;
    x.constant(&p.force_limit, "force-limit", c.force_limit);
    x.constant(&p.feed_min, "feed-min-default", c.feed_min_mm_per_rev);
    x.constant(&p.feed_max, "feed-max-default", c.feed_max_mm_per_rev);
    x.constant(&p.feed_programmed, "feed-programmed", c.feed_programmed_mm_per_rev);
    x.constant(&p.speed_programmed, "cutting-speed-programmed", c.speed_programmed_m_per_min);
    x.constant(&p.control_period, "control-period", c.period_s);
    x.constant(&p.rating, "rating", mp.rating.limit_max);
    machine = std::move(m);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  machine.reset();
}
