#pragma once
// lathectl_gauge's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-gauge.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_GAUGE_PINS(PIN, HEAD) \
  PIN(generator, float, in, 0, "V", in.generator_V, R"~(The transducer generator's signal u [V].)~") \
  PIN(x_pos, float, in, 0, "mm", glue, R"~(The infeed axis' position [mm] (the backstop's scale).)~") \
  PIN(rearm, bit, in, 0, "", in.rearm, R"~(Rising edge: a new part.)~") \
  PIN(spindle_revs, float, in, 0, "rev", glue, R"~(The spindle's angle [revolutions] (spindle.0.revs): where the interruptions are.)~") \
  PIN(part_angle_deg, float, in, 0, "deg", glue, R"~(Gate: the part's first interruption's middle at spindle angle 0 [deg].)~") \
  PIN(signal, float, out, 0, "V", out.signal_V, R"~(The filtered signal S [V].)~") \
  PIN(step, s32, out, 0, "", out.step, "") \
  PIN(step_f, float, out, 0, "", out.step, R"~(Commands operated (0 rough, 1 fine, 2 spark\-out, 3 size).)~") \
  PIN(command, s32, out, 0, "", out.command, R"~(The command in force: 0 rough, 1 fine, 2 spark\-out, 3 size.)~") \
  PIN(feed_scale, float, out, 0, "", glue, R"~(For motion.adaptive\-feed.)~") \
  PIN(probe, bit, out, 0, "", out.stop, R"~(For motion.probe\-input: the cut must end.)~") \
  PIN(feed_hold, bit, out, 0, "", glue, R"~(For motion.feed\-inhibit: a sensor alarm.)~") \
  PIN(size, bit, out, 0, "", out.size, "") \
  PIN(backstop, bit, out, 0, "", out.backstop, "") \
  PIN(alarm, bit, out, 0, "", out.alarm, "") \
  PIN(armed, bit, out, 0, "", out.armed, "") \
  PIN(unreachable, bit, out, 0, "", out.unreachable, R"~(The size command operated; the cut ended at the backstop; an alarm is latched; the relay is armed; the next threshold is above the free probe's signal.)~") \
  PIN(reason, s32, out, 0, "", out.reason, R"~(The decision's reason code (\fBlathectl reasons\fR): 61 gauge_step, 62 gauge_size, 60 gauge_backstop, 63 gauge_signal_lost, 64 gauge_unreachable, 65 gauge_no_round_surface, 10 sensor_not_finite.)~") \
  PIN(bridged, bit, out, 0, "", out.bridged, R"~(The sample was bridged (gate).)~") \
  PIN(threshold, float, out, 8, "V", glue, "") \
  PIN(next_threshold, float, out, 0, "V", out.next_threshold_V, R"~(The thresholds, one per step of GaugeMachine::kMaxSteps (unused ones 0), and the next to cross.)~") \
  PIN(trip_time, float, out, 0, "s", out.trip_time_s, "") \
  PIN(part_time, float, out, 0, "s", out.time_s, R"~(The last crossing's time and the time now [s] since the rearm.)~") \
  PIN(trips, s32, out, 0, "", out.tripped_steps, R"~(Thresholds crossed.)~") \
  PIN(stop_latency, float, out, 0, "s", glue, "") \
  PIN(trip_to_stop, float, out, 0, "s", glue, R"~(From the probe's assertion, and from the crossing, to the last sample at which the infeed still moved toward the part [s] (X moves in steps of the servo period).)~")
// clang-format on
