#pragma once
// Status and reason codes shared by every controller in control/.
//
// Every decision that limits, holds or alarms sets a Reason in the controller's Output, so a log
// (the recorder, a HAL pin) can say why the output is what it is.

#include <cstdint>
#include <string_view>

namespace lathectl::control {

// Result of one update() call. Ruckig-style: small, [[nodiscard]], no exceptions.
enum class Status : std::uint8_t {
  Ok = 0,       // output follows the control law
  Limited = 1,  // output clamped by a limit or a rate limit
  Hold = 2,     // output frozen or feed stopped (fault or alarm)
  NotConfigured = 3,
};

// Why the output is what it is. Values are stable: they are written to channels.csv and HAL pins.
enum class Reason : std::uint16_t {
  None = 0,
  OutputHigh = 1,          // regulator output at its upper limit (e.g. programmed feed)
  OutputLow = 2,           // regulator output at its lower limit
  RateLimited = 3,         // output slew limited (motor speed, converter ramp)
  SensorNotFinite = 10,    // sensor sample NaN or infinite
  SensorOutOfRange = 11,   // sensor sample outside its valid range
  SensorStuck = 12,        // sensor sample unchanged for longer than allowed
  SensorSuspect = 13,      // sensor sample unchanged for a few samples: output held, not raised
  Overload = 20,           // force above limit too long with feed already at minimum
  ToolBreakage = 21,       // sudden force drop or spike
  ToolDataChanged = 22,    // the tool's number, offsets or table row changed inside a feed move
  AirCut = 30,             // tool not in the cut: air feed
  Engaged = 31,            // tool entered the cut: feed dropped to the programmed value, PI preset
  NotInFeedBlock = 32,     // rapid / non-cutting block: adaptive control inactive
  SpindleSpeedLimit = 40,  // speed command clamped to the spindle's range
  SpindlePowerLimit = 41,  // speed command reduced to respect the spindle's power
  ModulationEngaged = 50,     // vibration above the dead zone: modulated feed formed and running
  ModulationReleased = 51,    // modulation stopped (below the dead zone, or the block ended)
  ModulationLimited = 52,     // the quenching condition needs more span than the limits allow
  ModulationProgrammed = 53,  // the NC block's own (S_min, ΔS, Δl, n_s) are running
  ModulationNoForce = 54,     // vibration seen but no cutting power/speed to size A_P: no plan
  GaugeBackstop = 60,  // the gauge's relay did not end the cut: the backstop position did (system D)
};

constexpr std::string_view reason_name(Reason r) noexcept {
  switch (r) {
    case Reason::None:
      return "none";
    case Reason::OutputHigh:
      return "output_high";
    case Reason::OutputLow:
      return "output_low";
    case Reason::RateLimited:
      return "rate_limited";
    case Reason::SensorNotFinite:
      return "sensor_not_finite";
    case Reason::SensorOutOfRange:
      return "sensor_out_of_range";
    case Reason::SensorStuck:
      return "sensor_stuck";
    case Reason::SensorSuspect:
      return "sensor_suspect";
    case Reason::Overload:
      return "overload";
    case Reason::ToolBreakage:
      return "tool_breakage";
    case Reason::ToolDataChanged:
      return "tool_data_changed";
    case Reason::AirCut:
      return "air_cut";
    case Reason::Engaged:
      return "engaged";
    case Reason::NotInFeedBlock:
      return "not_in_feed_block";
    case Reason::SpindleSpeedLimit:
      return "spindle_speed_limit";
    case Reason::SpindlePowerLimit:
      return "spindle_power_limit";
    case Reason::ModulationEngaged:
      return "modulation_engaged";
    case Reason::ModulationReleased:
      return "modulation_released";
    case Reason::ModulationLimited:
      return "modulation_limited";
    case Reason::ModulationProgrammed:
      return "modulation_programmed";
    case Reason::ModulationNoForce:
      return "modulation_no_force";
    case Reason::GaugeBackstop:
      return "gauge_backstop";
  }
  return "unknown";
}

constexpr bool is_alarm(Reason r) noexcept {
  return r == Reason::SensorNotFinite || r == Reason::SensorOutOfRange ||
         r == Reason::SensorStuck || r == Reason::Overload || r == Reason::ToolBreakage ||
         r == Reason::ToolDataChanged ||
         r == Reason::GaugeBackstop;
}

}  // namespace lathectl::control
