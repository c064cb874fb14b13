#pragma once
// lathectl_slide's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-slide.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_SLIDE_PINS(PIN, HEAD) \
  HEAD(R"~(The programming device (NC program conventions))~") \
  PIN(enable, bit, in, 0, "", in.enable, R"~(\(<- motion.digital\-out\-00: M64 P0 switches the slide on, M65 P0 off (valve shut, reason slide_off; the controller is not run, so a resting sensor is not "stuck"; at switch\-on it starts bumpless from the force read).)~") \
  PIN(roughing, bit, in, 0, "", glue, R"~(\(<- motion.digital\-out\-01: M64 P1 roughing (hold the force), M65 P1 finishing (hold the feed).)~") \
  PIN(reset, bit, in, 0, "", in.reset_alarm, R"~(\(<- motion.digital\-out\-02: rising edge (M64 P2, then M65 P2) clears a latched alarm.)~") \
  PIN(feed_set, float, in, 0, "mm/min", glue, R"~(\(<- motion.analog\-out\-00: M68 E0 Q\fIfeed\fR: the programmed feed (roughing: its ceiling); \(<= 0: the scenario's.)~") \
  PIN(force_set, float, in, 0, "N", glue, R"~(\(<- motion.analog\-out\-01: M68 E1 Q\fIforce\fR: roughing's force setpoint; \(<= 0: the scenario's.)~") \
  PIN(position, float, in, 0, "mm", glue, R"~(The slide's travel, where the laws are read.)~") \
  HEAD(R"~(The machine)~") \
  PIN(sensor_in, float, in, 0, "V", glue, "") \
  PIN(sensor_gain, float, io, 0, "", glue, "") \
  PIN(sensor_offset, float, io, 0, "", glue, R"~(The inductive sensor's analog input and its calibration: U_D = sensor\-in \(mu sensor\-gain + sensor\-offset [V] (default 1, 0).)~") \
  PIN(valve, bit, out, 0, "", glue, R"~((base thread) The spool's electromagnet: pulses of \(*Dt at the frequency in force.)~") \
  PIN(slot_cmd, float, out, 0, "mm", glue, "") \
  PIN(eccentric_pos_cmd, float, out, 0, "rad", glue, R"~(AIM: the slot and the eccentric's angle for it on the scenario's profile, the position command for the eccentric's motor (closed by its drive, or by a LinuxCNC pid on its feedback).)~") \
  PIN(frequency, float, out, 0, "Hz", out.frequency_Hz, "") \
  PIN(pulse_width, float, out, 0, "s", glue, R"~(The pulse frequency in force and the pulse width \(*Dt.)~") \
  PIN(sensor_V, float, out, 0, "V", glue, "") \
  PIN(force_estimate, float, out, 0, "N", out.force_estimate_N, "") \
  PIN(feed_cmd, float, out, 0, "mm/min", glue, "") \
  PIN(feed_set_out, float, out, 0, "mm/min", glue, "") \
  PIN(force_set_out, float, out, 0, "N", out.force_set_N, "") \
  PIN(roughing_out, bit, out, 0, "", glue, "") \
  PIN(enabled, bit, out, 0, "", out.enabled, R"~(What the machine does and from which program.)~") \
  PIN(alarm, bit, out, 0, "", out.alarm, "") \
  PIN(reason, s32, out, 0, "", out.reason, "") \
  PIN(alarm_reason, s32, out, 0, "", out.alarm_reason, R"~(The reason codes of \fBlathectl reasons\fR (hal/reasons.json).)~") \
  HEAD(R"~(Timing)~") \
  PIN(pulses, s32, out, 0, "", glue, "") \
  PIN(width_error_max_ns, s32, out, 0, "ns", glue, "") \
  PIN(period_error_max_ns, s32, out, 0, "ns", glue, "") \
  PIN(base_jitter_max_ns, s32, out, 0, "ns", glue, R"~(Pulses formed; the worst |measured width \- \(*Dt|, |measured rising\-to\-rising \- the programmed whole base periods| and |base\-thread interval \- its period|, on the RTAPI clock.)~") \
  PIN(width_error_mean_ns, float, out, 0, "ns", glue, "") \
  PIN(period_error_mean_ns, float, out, 0, "ns", glue, "") \
  PIN(base_jitter_mean_ns, float, out, 0, "ns", glue, R"~(Their means over every pulse (period, base\-thread call): the worst case is one late wake\-up, the mean what the hydraulics integrate.)~")
// clang-format on
