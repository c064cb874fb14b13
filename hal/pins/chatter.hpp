#pragma once
// lathectl_chatter's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-chatter.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_CHATTER_PINS(PIN, HEAD) \
  PIN(z_pos, float, in, 0, "", glue, R"~(Tool z [mm] (\fBjoint.N.pos\-fb\fR); the right turret's in a twin set\-up.)~") \
  PIN(z2_pos, float, in, 0, "", glue, R"~(The left turret's tool z [mm] (twin set\-ups; unused for one tool).)~") \
  PIN(spindle_revs, float, in, 0, "", glue, "") \
  PIN(spindle_rpm, float, in, 0, "", glue, R"~(Spindle position [revolutions] (\fBspindle.0.revs\fR) and speed [rpm].)~") \
  PIN(enable, bit, in, 0, "", glue, R"~(FALSE: the tool is far from the part.)~") \
  PIN(vibration_um, float, out, 0, "", glue, R"~(The part's displacement at the tool [\(*mm].)~") \
  PIN(vibration_peak_um, float, out, 0, "", glue, R"~(The largest |displacement high\-passed at the sensor's cut\-off| over the call's sub\-steps [\(*mm]: rig B's measure of the vibration (y_highpass), for a recorder that compares with \fBlathectl run\fR.)~") \
  PIN(a0_um, float, out, 0, "", glue, "") \
  PIN(omega_d_Hz, float, out, 0, "", glue, R"~(The detectors: amplitude [\(*mm] and frequency [Hz]; zero below the dead zone.)~") \
  PIN(radial_force, float, out, 0, "", glue, "") \
  PIN(tangential_force, float, out, 0, "", glue, R"~(F_p and F_c [N].)~") \
  PIN(cut_power, float, out, 0, "", glue, "") \
  PIN(spindle_power, float, out, 0, "", glue, R"~(Cutting power and the main motor's electrical power [W].)~") \
  PIN(chip, float, out, 0, "", glue, "") \
  PIN(depth, float, out, 0, "", glue, "") \
  PIN(in_contact, bit, out, 0, "", glue, R"~(Chip per revolution and depth [mm] while cutting.)~") \
  PIN(radial_force2, float, out, 0, "", glue, "") \
  PIN(chip2, float, out, 0, "", glue, "") \
  PIN(depth2, float, out, 0, "", glue, "") \
  PIN(in_contact2, bit, out, 0, "", glue, R"~(The same for the left turret's tool (twin set\-ups; zero for one tool). \fBradial\-force\fR, \fBtangential\-force\fR, \fBchip\fR, \fBdepth\fR and \fBin\-contact\fR are the right turret's; \fBcut\-power\fR and \fBspindle\-power\fR both tools'.)~") \
  PIN(diverged, bit, out, 0, "", glue, R"~(The part's displacement exceeded 50 mm (numerical divergence).)~")
// clang-format on
