#pragma once
// The pins every realtime function reports itself with (lathectl::hal::MeterPins), a pin table.
//
// A pin table (one per component, hal/pins/<component>.hpp) is an X-macro of rows
//   PIN(member, type, dir, count, unit, field, doc)
// member: the pin block's member; the pin is `prefix.` + the member with '_' -> '-' (so they
//   cannot differ); type: bit, float, s32 or u32; dir: in, out or io; count: 0 a scalar, n > 0
//   an array of n pins member-0 ... member-(n-1); unit: shown as [unit] ("" none); field: the
//   machine object's value the pin is copied to (an in pin: `in.<member of its Input>`) or from
//   (an out pin: `out.<member of its Output>`), each period, by the pin block's generated
//   read_pins/write_pins (LATHECTL_HAL_PIN_BLOCK), with the pin type's conversion and nothing
//   else; `glue` for a pin the component's own code reads or writes (a unit converted, a record
//   written in its order, a value that is the component's, not the machine's); doc: one line
//   of troff (a raw string); a row with an empty doc shares the next row's (one .TP in the man
//   page). HEAD(text) rows are the man page's .SS headings. No HAL headers: the components
//   (LATHECTL_HAL_PIN_BLOCK, lathectl_hal.hpp) and lathectl_hal_pin_docs both include it.
// clang-format off
#define LATHECTL_METER_PINS(PIN, HEAD) \
  PIN(period_error, bit, out, 0, "", glue, R"~(Latched: the thread's period is not the one the component was configured for, and the function does nothing.)~") \
  PIN(update_ns, s32, out, 0, "ns", glue, "") \
  PIN(update_ns_max, s32, out, 0, "ns", glue, R"~(The function's own wall time, on the monotonic clock, and the worst since load.)~")
// clang-format on
