#pragma once
// lathectl_vibsensor's pins, one table (its format: hal/pins/meter.hpp). A row PIN(member, ...)
// is the pin lathectl-vibsensor.<member with '_' -> '-'>; HEAD(text) is a heading of the man
// page. The component's pin block and export, and its man page's PINS section, are made from it.
// clang-format off
#define LATHECTL_VIBSENSOR_PINS(PIN, HEAD) \
  PIN(a0_um, float, out, 0, "", glue, "") \
  PIN(omega_d_Hz, float, out, 0, "", glue, R"~(The detectors on the accelerometer's signal, as \fBlathectl_chatter\fR's on the simulated part: amplitude (ADC 19) [\(*mm] and frequency (detector 20) [Hz]; zero below the dead zone. Net them to \fBlathectl\-modfeed.a0\-um\fR and \fBlathectl\-modfeed.omega\-d\-Hz\fR.)~") \
  PIN(vibration_um, float, out, 0, "", glue, R"~(The displacement integrated from the acceleration and high\-passed, before the dead zone, at the last sample [\(*mm].)~") \
  PIN(acceleration, float, out, 0, "m/s^2", glue, R"~(The largest |acceleration| of the last block read (about 10 ms).)~") \
  PIN(frames, u32, out, 0, "", glue, R"~(Samples read since start (wraps).)~") \
  PIN(overruns, u32, out, 0, "", glue, "") \
  PIN(clipped, u32, out, 0, "", glue, R"~(Capture overruns (samples lost: the chain's gates then span a gap) and samples at 99.9 % of the interface's full scale or beyond (raise \fB\-\-full\-scale\fR's range on the interface, or use a less sensitive accelerometer).)~") \
  PIN(running, bit, out, 0, "", glue, R"~(TRUE while the source delivers; FALSE once a recording has ended (its last outputs stay).)~")
// clang-format on
