#pragma once
// The pins every realtime function reports itself with (lathectl::hal::MeterPins), a pin table:
// PIN(member, type, dir, count, unit, doc), the pin named after the member with '_' → '-'; a row
// with an empty doc shares the next row's. No HAL headers: lathectl_hal_pin_docs reads it too.
// clang-format off
#define LATHECTL_METER_PINS(PIN, HEAD) \
  PIN(period_error, bit, out, 0, "", R"~(Latched: the thread's period is not the one the component was configured for, and the function does nothing.)~") \
  PIN(update_ns, s32, out, 0, "ns", "") \
  PIN(update_ns_max, s32, out, 0, "ns", R"~(The function's own wall time, on the monotonic clock, and the worst since load.)~")
// clang-format on
