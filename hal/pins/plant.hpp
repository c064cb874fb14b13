#pragma once
// lathectl_plant's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-plant.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_PLANT_PINS(PIN, HEAD) \
  PIN(x_pos, float, in, 0, "mm", glue, "") \
  PIN(z_pos, float, in, 0, "mm", glue, R"~(Tool position [mm]: radius and z, joint positions (\fBjoint.N.pos\-fb\fR).)~") \
  PIN(spindle_rpm, float, in, 0, "rpm", in.rpm, R"~(Actual spindle speed [rpm] (sign ignored).)~") \
  PIN(enable, bit, in, 0, "", glue, R"~(FALSE (e.g. before homing): no position, nothing is cut, the sensor reads its noise.)~") \
  PIN(force, float, out, 0, "", out.force_measured, R"~(The sensor's sample of the force parameter [N, or W for power].)~") \
  PIN(force_true, float, out, 0, "", out.force_parameter, R"~(Its true value.)~") \
  PIN(pz, float, out, 0, "N", out.Pz_N, "") \
  PIN(py, float, out, 0, "N", out.Py_N, R"~(Tangential and radial force [N].)~") \
  PIN(cut_power, float, out, 0, "W", out.cut_power_W, R"~(Cutting power Pz\(mdV [W].)~") \
  PIN(depth, float, out, 0, "mm", out.depth_mm, "") \
  PIN(feed_per_rev, float, out, 0, "mm/rev", out.feed_per_rev_mm, R"~(Depth of cut t [mm] (with runout and random allowance) and feed s [mm/rev].)~") \
  PIN(cutting_speed, float, out, 0, "m/min", out.speed_m_per_min, R"~(V [m/min] at the uncut surface (0 out of the cut).)~") \
  PIN(strength_factor, float, out, 0, "", out.strength_factor, R"~(Local hardness factor of the scenario.)~") \
  PIN(in_contact, bit, out, 0, "", out.in_contact, R"~(The tool is cutting.)~") \
  PIN(time_in_cut, float, out, 0, "s", out.time_in_cut_s, R"~(Seconds in cut (drives tool wear).)~") \
  PIN(motion_type, s32, in, 0, "", glue, R"~(\fBmotion.motion\-type\fR: feed moves are 2 and 3 (default 2 when unconnected).)~") \
  PIN(force_rev_mean, float, out, 0, "", glue, "") \
  PIN(force_rev_peak, float, out, 0, "", glue, R"~(The true force parameter's mean over the trailing spindle revolution in feed moves (a rapid through material counts as 0 here: it is reported apart), and its largest value over the cuts, each cut's first revolution left out (the chip is still building). The same rule as lathectl run's \fBforce_peak_rev_mean_N\fR, which linuxcnc\-sim's summary takes from this pin.)~") \
  PIN(update_ns, s32, out, 0, "ns", glue, "") \
  PIN(update_ns_max, s32, out, 0, "ns", glue, R"~(Duration of the last step and the worst since load [ns].)~") \
  PIN(spindle_power, float, out, 0, "W", glue, R"~(What the spindle drive's power pin reads [W]: drawn(P_cut + J\(md\(*w\(mdd\(*w/dt + b\(md\(*w\(S2) + P_idle(n)\(md(1 + d\(mde^\-t/\(*t) through the power meter, where drawn(P) is P/\(*h motoring and P\(md\(*h braking: the law of rig E's spindle drive (drives::SpindlePowerAtSpeed) at LinuxCNC's speed, with the scenario's \fB[spindle]\fR (efficiency \(*h, inertia J, friction b, seed 001's idle law p0 + p1\(mdn + p2\(mdn\(S2); a cold machine draws \fBidle_drift\fR d (default 0.15) more idle power, falling off with \fBwarmup_s\fR \(*t (default 120 s) after the load. The meter is the scenario's \fB[sensor]\fR power meter (\fBpower_meter_time_constant_ms\fR, \fBpower_meter_noise_W\fR; sensor 4 itself when its \fBparameter\fR is power), as in \fBlathectl run\fR; without the scenario's noise, 0.1 % of the rated power (a noiseless reading would be called stuck). The same lag is what lathectl_adaptive takes off the acceleration power. What lathectl_adaptive sensor=power reads.)~") \
  PIN(idle_power, float, out, 0, "W", glue, "") \
  PIN(idle_drift_factor, float, out, 0, "", glue, R"~(The true idle power in it [W] and 1 + d\(mde^\-t/\(*t (for tests of the learned tare).)~") \
  PIN(tool_number, s32, in, 0, "", glue, R"~(\fBiocontrol.0.tool\-number\fR: the tool in the spindle (its insert in \fBtool_file\fR, its nose and orientation in \fBtool_table\fR).)~") \
  PIN(insert_width, float, out, 0, "mm", glue, R"~(The width of cut the plant takes [mm]: in a feed move, the insert width of a grooving or parting tool\-number in \fBtool_file\fR (its whole width cuts, the feed per revolution its chip thickness, as \fBlathectl optimize\fR predicts it); 0: the nose at its engagement.)~") \
  PIN(probe_z, float, in, 0, "mm", glue, "") \
  PIN(probe_radius, float, out, 0, "mm", glue, R"~(The workpiece's radius now at machine z \fBprobe\-z\fR (what the stock model holds; for tests and for finding where material went).)~")
// clang-format on
