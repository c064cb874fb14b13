#pragma once
// lathectl_gauge_plant's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-gauge-plant.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_GAUGE_PLANT_PINS(PIN, HEAD) \
  PIN(x_pos, float, in, 0, "mm", glue, R"~(The tool's X [mm].)~") \
  PIN(spindle_revs, float, in, 0, "rev", glue, R"~(The spindle's angle [revolutions] (spindle.0.revs).)~") \
  PIN(load, bit, in, 0, "", glue, R"~(Rising edge: a new blank.)~") \
  PIN(break_wire, bit, in, 0, "", glue, R"~(The generator's wire is open: \fBgenerator\fR reads 0.)~") \
  PIN(generator, float, out, 0, "V", glue, R"~(The generator's signal u [V].)~") \
  PIN(size_um, float, out, 0, "um", glue, "") \
  PIN(error_um, float, out, 0, "um", glue, R"~(The part's controlled size x and x \- target [\(*mm].)~") \
  PIN(finished_error_um, float, out, 0, "um", glue, R"~(The previous part's x \- target when the next one was loaded [\(*mm].)~") \
  PIN(radius, float, out, 0, "mm", glue, R"~(The part's radius [mm].)~") \
  PIN(disturbance_um, float, out, 0, "um", glue, "") \
  PIN(wear_um, float, out, 0, "um", glue, R"~(\(*x and the tool's wear [\(*mm].)~") \
  PIN(part, s32, out, 0, "", glue, R"~(Parts loaded.)~") \
  PIN(in_contact, bit, out, 0, "", glue, R"~(The tool removed material in this period.)~") \
  PIN(part_angle_deg, float, out, 0, "deg", glue, R"~(The part's orientation: its first interruption's middle at spindle angle 0 [deg].)~") \
  PIN(interruption_um, float, out, 0, "um", glue, R"~(The interruption's depth under the probe [\(*mm] (0 on the round surface).)~")
// clang-format on
