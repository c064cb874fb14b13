#pragma once
// lathectl_adaptive's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-adaptive.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_ADAPTIVE_PINS(PIN, HEAD) \
  PIN(force, float, in, 0, "N or W", in.force, R"~(Force parameter (sensor 4), in the scenario's unit: N for Pz/Py, W for cutting power.)~") \
  PIN(spindle_rpm, float, in, 0, "rpm", in.rpm, R"~(Actual spindle speed [rpm] (sensor 13).)~") \
  PIN(spindle_rpm_programmed, float, in, 0, "rpm", in.rpm_programmed, R"~(The program's spindle speed [rpm], e.g. \fBspindle.0.speed\-out\fR.)~") \
  PIN(current_vel, float, in, 0, "mm/s", in.current_vel_mm_s, R"~(Actual path velocity [mm/s], e.g. \fBmotion.current\-vel\fR (sensor 12, for S_cur).)~") \
  PIN(operator_override, float, in, 0, "", in.knob, R"~(The operator's feed override (1 = 100 %, at most \fImax\-feed\-override\fR; NaN or negative stops the feed). Default 1.)~") \
  PIN(max_feed_override, float, in, 0, "", in.max_override, R"~(\fB[DISPLAY]MAX_FEED_OVERRIDE\fR: the highest net override. Default 1 (never above the program).)~") \
  PIN(feed_override_in_motion, float, in, 0, "", in.scale_in_motion, R"~(The feed scale motion reports, \fBhalui.feed\-override.value\fR.)~") \
  PIN(feed_override, float, out, 0, "", out.feed_override, R"~(The feed scale to command (the net override's ceiling), rounded up to 0.001.)~") \
  PIN(feed_override_counts, s32, out, 0, "", out.feed_override_counts, R"~(The same in thousandths, for \fBhalui.feed\-override.counts\fR (direct\-value, scale 0.001).)~") \
  PIN(feed_factor, float, out, 0, "", out.feed_factor, R"~(The net override of the program's feed: operator's override \(mu the controller's factor, at most \fImax\-feed\-override\fR (0 while the feed is held). The operation log's feed.)~") \
  PIN(load_percent, float, out, 0, "%", out.load_percent, R"~(\fIload\-rev\fR in % of the limit (the operator panel's bar).)~") \
  PIN(requested_vel, float, in, 0, "", in.requested_vel, R"~(\fBmotion.requested\-vel\fR: the program's feed [mm/s under G94, mm/rev under G95]. A new value is used once it has held for one thread period (motion changes it a period before \fBmotion.motion\-type\fR at a block change).)~") \
  PIN(feed_upm, float, in, 0, "mm/min", in.feed_upm, R"~(\fBmotion.feed\-upm\fR: the move's F word times motion's net feed scale; under G95 the program's feed per revolution is taken from it (see above).)~") \
  PIN(motion_type, s32, in, 0, "", in.motion_type, R"~(\fBmotion.motion\-type\fR; 2 (linear feed) and 3 (arc) are feed blocks, anything else makes the controller inactive (bumpless restart at the next feed block).)~") \
  PIN(x_pos, float, in, 0, "mm", in.x_mm, R"~(Tool radius [mm] (joint 0 position of a lathe), for the cutting speed when \fIcutting\-speed\fR is not wired.)~") \
  PIN(cutting_speed, float, in, 0, "m/min", in.cutting_speed_m_per_min, R"~(Measured cutting speed [m/min] (sensor 20). When zero, \(*p\(md2\(mdx\-pos\(mdrpm/1000 is used.)~") \
  PIN(spindle_power, float, in, 0, "W", in.spindle_power_W, R"~(The spindle drive's electrical power [W] (its power meter). With a \fBPy\fR sensor the cutting power for the speed law's power limit is this minus the scenario's idle power p0 + p1\(mdn + p2\(mdn\(S2; unwired (0), there is no power limit. A \fBPz\fR sensor gives the cutting power as Pz\(mdV/60, a power sensor its own reading; then this pin is used only while \fIforce\fR is not finite.)~") \
  PIN(feed_per_rev_mode, bit, in, 0, "", in.per_rev, R"~(TRUE when the program feeds per revolution (G95).)~") \
  PIN(enable, bit, in, 0, "", in.enable, R"~(FALSE: pass\-through (adaptive\-feed 1, the program's spindle speed, no hold).)~") \
  PIN(reset, bit, in, 0, "", in.reset, R"~(A rising edge resets a latched alarm.)~") \
  PIN(reset_max, bit, in, 0, "", glue, R"~(While TRUE, \fIupdate\-ns\-max\fR restarts.)~") \
  PIN(adaptive_feed, float, out, 0, "", out.adaptive_feed, R"~(To \fBmotion.adaptive\-feed\fR: 0..1.)~") \
  PIN(feed_hold, bit, out, 0, "", out.feed_hold, R"~(Feed hold requested (alarm): to \fBmotion.feed\-inhibit\fR.)~") \
  PIN(spindle_speed_out, float, out, 0, "rpm", out.spindle_speed_out, R"~(Spindle speed command [rpm]: the speed law's in \fBforce_speed\fR mode while the program runs the spindle (sign of the program's), else the program's speed.)~") \
  PIN(spindle_override, float, out, 0, "", out.spindle_override, R"~(spindle\-speed\-out / spindle\-rpm\-programmed.)~") \
  PIN(alarm, bit, out, 0, "", out.alarm, R"~(A latched alarm.)~") \
  PIN(reason, s32, out, 0, "", out.reason, R"~(Why the output is what it is: 0 none, 1 output_high, 2 output_low, 3 rate_limited, 10 sensor_not_finite, 11 sensor_out_of_range, 12 sensor_stuck, 13 sensor_suspect, 20 overload, 21 tool_breakage, 22 tool_data_changed, 30 air_cut, 31 engaged, 32 not_in_feed_block, 33 stock_ahead, 34 power_acceleration_unknown (sensor=power with learn_inertia: a speed change in a cut before the inertia is learned; the feed may fall, not rise), 40 spindle_speed_limit, 41 spindle_power_limit. \fBlathectl reasons\fR prints every code with its meaning and whether it is an alarm.)~") \
  PIN(alarm_reason, s32, out, 0, "", out.alarm_reason, R"~(The latched alarm's reason (same codes).)~") \
  PIN(feed_per_rev, float, out, 0, "mm/rev", out.feed_per_rev_mm, R"~(The controller's feed [mm/rev] (0 on hold).)~") \
  PIN(cutting_speed_cmd, float, out, 0, "m/min", out.speed_cmd_m_per_min, "") \
  PIN(cutting_speed_opt, float, out, 0, "m/min", out.speed_opt_m_per_min, R"~(Commanded cutting speed and seed 004's V_opt [m/min].)~") \
  PIN(cut_power, float, out, 0, "W", out.cut_power_W, R"~(The cutting power [W] the speed law's power limit used in the last step (see \fIspindle\-power\fR).)~") \
  PIN(in_cut, bit, out, 0, "", out.in_cut, R"~(The tool is in the material (force above the air threshold).)~") \
  PIN(period_error, bit, out, 0, "", out.period_error, R"~(The control period is not a whole multiple of the thread period.)~") \
  PIN(update_ns, s32, out, 0, "ns", glue, "") \
  PIN(update_ns_max, s32, out, 0, "ns", glue, R"~(Duration of the last controller step and the worst since load [ns], monotonic clock around the step.)~") \
  PIN(limit_cmd, float, in, 0, "N or W", in.limit_cmd, "") \
  PIN(feed_min_cmd, float, in, 0, "mm/rev", in.feed_min_cmd, "") \
  PIN(feed_max_cmd, float, in, 0, "mm/rev", in.feed_max_cmd, "") \
  PIN(mode_cmd, float, in, 0, "", in.mode_cmd, "") \
  PIN(operation_cmd, float, in, 0, "", in.operation_cmd, R"~(\fBmotion.analog\-out\-00\fR .. \fB04\fR (above).)~") \
  PIN(tool_number, s32, in, 0, "", in.tool_number, R"~(\fBiocontrol.0.tool\-number\fR.)~") \
  PIN(tool_diameter, float, in, 0, "mm", in.tool_diameter, "") \
  PIN(tool_offset_x, float, in, 0, "mm", in.tool_offset_x, "") \
  PIN(tool_offset_z, float, in, 0, "mm", in.tool_offset_z, R"~(\fBhalui.tool.diameter\fR, \fBmotion.tooloffset.x\fR, \fBmotion.tooloffset.z\fR: watched for a change inside a feed move (above). Unwired: 0, never a change.)~") \
  PIN(tool_data_changed, bit, out, 0, "", out.tool_data_changed, R"~(The latched alarm 22: the tool's data changed inside a feed move.)~") \
  PIN(z_pos, float, in, 0, "mm", in.z_mm, "") \
  PIN(homed, bit, in, 0, "", glue, R"~(Joint 1's position and \fBmotion.is\-all\-homed\fR: the stock model's path.)~") \
  PIN(predicted_depth, float, out, 0, "mm", out.predicted_depth_mm, "") \
  PIN(breakage, bit, out, 0, "", out.breakage, R"~(The stock model's depth of cut at the tool [mm] and the latched path\-aware breakage alarm.)~") \
  PIN(depth_ahead, float, out, 0, "mm", out.depth_ahead_mm, "") \
  PIN(feed_ceiling, float, out, 0, "mm/rev", out.feed_ceiling_mm_per_rev, "") \
  PIN(specific_force, float, out, 0, "", out.specific_force_ratio, R"~(The feed\-forward: the stock model's depth of cut ahead of the tool [mm], the ceiling it puts on the feed [mm/rev] (0: none) and \(*k, the measured load over the handbook law's.)~") \
  PIN(inertia, float, out, 0, "kg*m^2", out.inertia_kg_m2, R"~(The spindle's inertia J in use [kg\(mum\(S2]: the scenario's, or with \fBlearn_inertia = true\fR in its \fB[controller]\fR the one learned from the drive's power in speed changes in air (the least\-squares slope of the drive's power above idle on \(*w\(md\(*w/dt).)~") \
  PIN(program_line, s32, in, 0, "", in.program_line, R"~(\fBmotion.program\-line\fR (operation records, bad\-line).)~") \
  PIN(load, float, out, 0, "N or W", out.load, "") \
  PIN(load_rev, float, out, 0, "N or W", out.load_rev, R"~(The load the controller sees (N or W) and its mean over the last revolution in the cut.)~") \
  PIN(limit, float, out, 0, "N or W", out.limit, "") \
  PIN(feed_min, float, out, 0, "mm/rev", out.feed_min, "") \
  PIN(feed_max, float, out, 0, "mm/rev", out.feed_max, "") \
  PIN(adaptive_on, bit, out, 0, "", out.adaptive_on, "") \
  PIN(teaching, bit, out, 0, "", out.teaching, R"~(The settings in effect.)~") \
  PIN(bad_setting, bit, out, 0, "", out.bad_setting, "") \
  PIN(bad_code, s32, out, 0, "", out.bad_code, "") \
  PIN(bad_line, s32, out, 0, "", out.bad_line, "") \
  PIN(bad_value, float, out, 0, "", out.bad_value, R"~(A refused value (above).)~") \
  PIN(idle_power, float, out, 0, "W", out.idle_power_W, "") \
  PIN(idle_p0, float, out, 0, "W", out.idle_law[0], "") \
  PIN(idle_p1, float, out, 0, "W/rpm", out.idle_law[1], "") \
  PIN(idle_p2, float, out, 0, "W/rpm^2", out.idle_law[2], "") \
  PIN(tare_ready, bit, out, 0, "", out.tare_ready, R"~(The learned idle power at the current speed [W] and its law's coefficients (sensor=power).)~") \
  PIN(overload_warn, bit, out, 0, "", out.overload_warn, "") \
  PIN(overload_hold, bit, out, 0, "", out.overload_hold, R"~(The table's overload levels (above).)~") \
  PIN(op_seq, s32, out, 0, "", glue, "") \
  PIN(op_line, s32, out, 0, "", glue, "") \
  PIN(op_tool, s32, out, 0, "", glue, "") \
  PIN(op_operation, s32, out, 0, "", glue, "") \
  PIN(op_mode, s32, out, 0, "", glue, "") \
  PIN(op_reasons, s32, out, 0, "", glue, "") \
  PIN(op_alarm, s32, out, 0, "", glue, "") \
  PIN(op_limit, float, out, 0, "N or W", glue, "") \
  PIN(op_load_mean, float, out, 0, "N or W", glue, "") \
  PIN(op_load_peak, float, out, 0, "N or W", glue, "") \
  PIN(op_feed_min, float, out, 0, "", glue, "") \
  PIN(op_feed_mean, float, out, 0, "", glue, "") \
  PIN(op_time_in_cut, float, out, 0, "s", glue, "") \
  PIN(op_time, float, out, 0, "s", glue, R"~(The last finished operation: line, tool, operation number, mode, the reasons seen in the cut (a bit per reason code: bit \fIb\fR is the code at position \fIb\fR of the reason table, the \fBbit\fR column of \fBlathectl reasons\fR, so 1<<12 is 31 engaged), the first alarm, limit, per\-revolution mean load (mean and peak), adaptive feed (min and mean), time in cut and on the line [s].)~") \
  PIN(teach_seq, s32, out, 0, "", glue, "") \
  PIN(teach_tool, s32, out, 0, "", glue, "") \
  PIN(teach_operation, s32, out, 0, "", glue, "") \
  PIN(teach_reference, float, out, 0, "N or W", glue, R"~(The last reference taught.)~")
// Its read-only parameters, the scenario's settings as the machine runs them: rows
// PARAM(member, unit, field, doc), field an expression of the machine's Params `params`.
#define LATHECTL_ADAPTIVE_PARAMS(PARAM) \
  PARAM(force_limit, "N or W", params.controller.load_limit, R"~(The load limit (force, or power with a power sensor).)~") \
  PARAM(feed_min_default, "mm/rev", params.controller.feed_min_mm_per_rev, "") \
  PARAM(feed_max_default, "mm/rev", params.controller.feed_max_mm_per_rev, R"~(The feed bounds when the program sets none.)~") \
  PARAM(feed_programmed, "mm/rev", params.controller.feed_programmed_mm_per_rev, "") \
  PARAM(cutting_speed_programmed, "m/min", params.controller.speed_programmed_m_per_min, R"~(The scenario's programmed feed and cutting speed.)~") \
  PARAM(control_period, "s", params.controller.period_s, R"~(The control period.)~") \
  PARAM(rating, "N or W", params.rating.limit_max, R"~(The largest limit a program may set.)~")
// clang-format on
