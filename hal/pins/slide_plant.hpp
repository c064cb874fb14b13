#pragma once
// lathectl_slide_plant's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-slide-plant.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_SLIDE_PLANT_PINS(PIN, HEAD) \
  PIN(run, bit, in, 0, "", glue, "") \
  PIN(valve, bit, in, 0, "", glue, "") \
  PIN(eccentric_pos_cmd, float, in, 0, "rad", glue, R"~(The slide switched on, the spool's electromagnet, the eccentric motor's position command.)~") \
  PIN(frequency, float, in, 0, "Hz", glue, "") \
  PIN(force_estimate, float, in, 0, "N", glue, "") \
  PIN(reason, s32, in, 0, "", glue, "") \
  PIN(alarm, bit, in, 0, "", glue, R"~(The controller's (the frequency sets the feed's averaging window), recorded with the plant's channels.)~") \
  PIN(sensor_out, float, out, 0, "V", glue, R"~(The inductive sensor's output (faults included): lathectl_slide's sensor\-in.)~") \
  PIN(force, float, out, 0, "N", glue, "") \
  PIN(position, float, out, 0, "mm", glue, "") \
  PIN(slot, float, out, 0, "mm", glue, "") \
  PIN(eccentric_pos_fb, float, out, 0, "rad", glue, "") \
  PIN(plant_time, float, out, 0, "s", glue, "") \
  PIN(done, bit, out, 0, "", glue, R"~(The plant: the cutting force, the slide's travel, the eccentric's slot and its angle on the scenario's profile (AIM only), the plant's clock since \fBrun\fR first went high; \fBdone\fR high from run.duration_s on.)~")
// clang-format on
