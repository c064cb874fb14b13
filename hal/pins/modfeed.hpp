#pragma once
// lathectl_modfeed's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-modfeed.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_MODFEED_PINS(PIN, HEAD) \
  PIN(a0_um, float, in, 0, "um", glue, R"~(Vibration amplitude from the amplitude detector (ADC 19) [\(*mm]; 0 below the dead zone.)~") \
  PIN(omega_d_Hz, float, in, 0, "Hz", glue, R"~(Vibration frequency from the frequency detector 20 [Hz]; 0 below the dead zone.)~") \
  PIN(spindle_power, float, in, 0, "W", glue, R"~(Main motor's active power (sensor 11) [W].)~") \
  PIN(spindle_rpm, float, in, 0, "rpm", glue, R"~(Spindle speed [rpm].)~") \
  PIN(x_pos, float, in, 0, "mm", glue, R"~(Tool radius [mm], for the cutting speed V = 2\(*p|x|n/1000.)~") \
  PIN(requested_vel, float, in, 0, "", glue, "") \
  PIN(current_vel, float, in, 0, "mm/s", glue, R"~(\fBmotion.requested\-vel\fR (the program's feed: mm/s under G94, the F word under G95) and \fBmotion.current\-vel\fR (the path speed that advances the staircase) [mm/s].)~") \
  PIN(motion_type, s32, in, 0, "", glue, "") \
  PIN(feed_per_rev_mode, bit, in, 0, "", glue, R"~(\fBmotion.motion\-type\fR (2 and 3 are feed moves) and whether the program runs G95.)~") \
  PIN(idle_block, bit, in, 0, "", glue, R"~(The NC block is flagged idle: the idle power is stored (switch 12, compensator 13).)~") \
  PIN(turret_left, bit, in, 0, "", glue, R"~(The block's turret flag (default from the scenario). The output modulates only the flagged turret's path: with \fBoutput=adaptive\fR on LinuxCNC's one\-path lathe that is the path itself; with \fBoutput=eoffset\fR the right turret's axis (\fBaxis\-pos\-right\fR) or the left one's.)~") \
  PIN(source, s32, in, 0, "", glue, R"~(0 no modulation, 1 programmed, 2 automatic (default from the scenario).)~") \
  PIN(prog_s_min, float, in, 0, "mm/min", glue, "") \
  PIN(prog_ds, float, in, 0, "mm/min", glue, "") \
  PIN(prog_dl, float, in, 0, "mm", glue, "") \
  PIN(prog_n_s, s32, in, 0, "", glue, R"~(The block's programmed (S_min, \(*DS, \(*Dl, n_s); n_s > 0 selects the programmed variant.)~") \
  PIN(axis_pos_right, float, in, 0, "mm", glue, "") \
  PIN(axis_pos_left, float, in, 0, "mm", glue, R"~(\fBoutput=eoffset\fR: the turrets' axial axes' planned positions (\fBaxis.w.pos\-cmd\fR, \fBaxis.z.pos\-cmd\fR) [mm].)~") \
  PIN(axis_eoffset_right, float, in, 0, "mm", glue, "") \
  PIN(axis_eoffset_left, float, in, 0, "mm", glue, R"~(\fBoutput=eoffset\fR: the offsets motion applies to them (\fBaxis.\fIL\fB.eoffset\fR) [mm].)~") \
  PIN(enable, bit, in, 0, "", glue, R"~(FALSE: no modulation, output 1/\fIceiling\fR (default TRUE).)~") \
  PIN(adaptive_feed, float, out, 0, "", glue, R"~(To \fBmotion.adaptive\-feed\fR.)~") \
  PIN(feed, float, out, 0, "mm/min", glue, R"~(The modulated feed [mm/min].)~") \
  PIN(feed_ratio, float, out, 0, "", glue, R"~(S(t)/S_p, 1 while not modulating.)~") \
  PIN(eoffset_counts, s32, out, 0, "", glue, "") \
  PIN(eoffset_scale, float, out, 0, "", glue, R"~(\fBoutput=eoffset\fR: to \fBaxis.\fIL\fB.eoffset\-counts\fR and \fB\-scale\fR of both turrets' axes (1e\-5 mm a count).)~") \
  PIN(eoffset_enable_right, bit, out, 0, "", glue, "") \
  PIN(eoffset_enable_left, bit, out, 0, "", glue, R"~(\fBoutput=eoffset\fR: to \fBaxis.\fIL\fB.eoffset\-enable\fR: the flagged turret's axis takes the offset.)~") \
  PIN(eoffset, float, out, 0, "mm", glue, "") \
  PIN(axis_vel, float, out, 0, "mm/s", glue, R"~(\fBoutput=eoffset\fR: the offset asked for [mm] and the flagged axis's planned velocity [mm/s].)~") \
  PIN(cut_power, float, out, 0, "W", glue, R"~(N_c = N_m \- N_idle [W].)~") \
  PIN(engaged, bit, out, 0, "", glue, "") \
  PIN(reason, s32, out, 0, "", glue, R"~(Modulating, and why: 50 engaged, 51 released, 52 limited (the quenching condition wants more span than the limits allow), 53 programmed, 54 no cutting power to size A_P, 55 no idle power stored yet (no idle block has run, no idle table): no plan.)~") \
  PIN(s_min, float, out, 0, "mm/min", glue, "") \
  PIN(ds, float, out, 0, "mm/min", glue, "") \
  PIN(dl, float, out, 0, "mm", glue, "") \
  PIN(n_s, s32, out, 0, "", glue, R"~(The running plan.)~") \
  PIN(omega_m_Hz, float, out, 0, "Hz", glue, "") \
  PIN(ap_required, float, out, 0, "N", glue, "") \
  PIN(ap_planned, float, out, 0, "N", glue, R"~(Modulation frequency [Hz]; the force amplitude the quenching condition asks for and the one the plan gives [N].)~") \
  PIN(period_error, bit, out, 0, "", glue, R"~(The thread period does not divide 1 ms: the module stays off.)~") \
  PIN(update_ns, s32, out, 0, "ns", glue, "") \
  PIN(update_ns_max, s32, out, 0, "ns", glue, "") \
  PIN(reset_max, bit, in, 0, "", glue, R"~(Wall time of the last and of the slowest module update; a TRUE \fBreset\-max\fR starts the worst case over.)~") \
  PIN(plans_inline, s32, out, 0, "", glue, "") \
  PIN(plans_taken, s32, out, 0, "", glue, R"~(Plans the servo function made itself (no \fBlathectl\-modfeed.plan\fR running) and plans it took from \fBlathectl\-modfeed.plan\fR, since the component was loaded.)~") \
  PIN(plans_made, s32, out, 0, "", glue, R"~(Plans \fBlathectl\-modfeed.plan\fR made (written by that function). A plan asked for in a block that ends before it comes is made but not taken.)~")
// Its read-only parameters: rows PARAM(member, unit, field, doc), field an expression of the
// machine's Params `params`.
#define LATHECTL_MODFEED_PARAMS(PARAM) \
  PARAM(ceiling, "", params.ceiling, R"~(The ceiling in use: the program's F over the mean feed kept.)~") \
  PARAM(coefficient, "", params.module.coefficient, R"~(c, the coefficient of the force amplitude's condition.)~") \
  PARAM(part_mass, "kg", params.module.part_mass_kg, R"~(m_d, the part's modal mass.)~") \
  PARAM(dead_zone, "um", params.vibration.dead_zone_m * 1e6, R"~(Setter 18's dead zone: the vibration amplitude above which the module modulates (the threshold \fBlathectl_publish\fR shows \fIa0\-um\fR against).)~")
// clang-format on
