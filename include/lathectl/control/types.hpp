#pragma once
// The reason codes shared by every controller in control/.
//
// Every decision that limits, holds or alarms sets a Reason in the controller's Output, so a log
// (the recorder, a HAL pin) can say why the output is what it is.

#include <cstdint>
#include <string_view>

namespace lathectl::control {

// What LinuxCNC's motion.motion-type says the move in progress is (EMC_MOTION_TYPE_* of
// src/emc/motion/motion.h: 4 tool change, 5 probing and 6 rotary indexing are none of these).
// The machine sides, their hosts and the optimiser read it.
enum class Motion : std::int32_t { None = 0, Traverse = 1, Feed = 2, Arc = 3 };
// A feed block (a straight feed or an arc): where the feed controllers act and a cut is counted.
[[nodiscard]] constexpr bool is_feed_motion(std::int32_t type) noexcept {
  return type == static_cast<std::int32_t>(Motion::Feed) ||
         type == static_cast<std::int32_t>(Motion::Arc);
}
[[nodiscard]] constexpr bool is_feed_motion(double type) noexcept {  // a recorded column
  return type == static_cast<double>(Motion::Feed) || type == static_cast<double>(Motion::Arc);
}

// Why the output is what it is. Values are stable: they are written to channels.csv and HAL pins.
// What each means, and whether it is an alarm: kReasons below.
enum class Reason : std::uint16_t {
  None = 0,
  OutputHigh = 1,
  OutputLow = 2,
  RateLimited = 3,
  SensorNotFinite = 10,
  SensorOutOfRange = 11,
  SensorStuck = 12,
  SensorSuspect = 13,
  Overload = 20,
  ToolBreakage = 21,
  ToolDataChanged = 22,
  AirCut = 30,
  Engaged = 31,
  NotInFeedBlock = 32,
  StockAhead = 33,
  SpindleSpeedLimit = 40,
  SpindlePowerLimit = 41,
  ModulationEngaged = 50,
  ModulationReleased = 51,
  ModulationLimited = 52,
  ModulationProgrammed = 53,
  ModulationNoForce = 54,
  GaugeBackstop = 60,
  GaugeStep = 61,
  GaugeSize = 62,
  GaugeSignalLost = 63,
  GaugeUnreachable = 64,
  GaugeNoRoundSurface = 65,
  SlideOff = 70,
  ModulationNoIdle = 55,
  PowerAccelerationUnknown = 34,
};

// The one reason table: what each code means to an operator who reads it on a pin or in a log,
// whether it latches an alarm, and which systems' controllers set it. reason_name(), is_alarm()
// and the operation log's bits (reason_bit) are read from it; `lathectl reasons` prints it and
// hal/reasons.json publishes it to the Python side (lathectl_oplog.py, the headless display).
struct ReasonInfo {
  Reason code;
  std::string_view name;     // as written to channels.csv, operations.csv and reports
  bool alarm;                // latches an alarm: the feed is held until the alarm is reset
  std::string_view systems;  // the systems whose machine side sets it ("A E")
  std::string_view meaning;  // one sentence for an operator
};

inline constexpr ReasonInfo kReasons[] = {
    {Reason::None, "none", false, "A B D E",
     "The output follows the control law: nothing limits or holds it."},
    {Reason::OutputHigh, "output_high", false, "A E",
     "The regulator's output is at its upper limit (the programmed feed, the largest slot): the "
     "force is below its set value and cannot be raised further."},
    {Reason::OutputLow, "output_low", false, "A E",
     "The regulator's output is at its lower limit (the minimum feed or slot): the force stays "
     "above its set value."},
    {Reason::RateLimited, "rate_limited", false, "A E",
     "The output is changing as fast as it may (feed ramp, converter ramp) and has not reached "
     "its target yet."},
    {Reason::SensorNotFinite, "sensor_not_finite", true, "A D E",
     "The force or power sensor (D: the gauge's generator) reads NaN or infinity (a broken wire, a failed conversion): the "
     "feed is held until the alarm is reset."},
    {Reason::SensorOutOfRange, "sensor_out_of_range", true, "A E",
     "The sensor reads outside its valid range: the feed is held until the alarm is reset."},
    {Reason::SensorStuck, "sensor_stuck", true, "A E",
     "The sensor's reading has not changed in a cut for longer than allowed: the feed is held "
     "until the alarm is reset."},
    {Reason::SensorSuspect, "sensor_suspect", false, "A E",
     "The sensor's reading has not changed for a few samples: the feed may fall but not rise "
     "until the reading moves again."},
    {Reason::Overload, "overload", true, "A E",
     "The force stayed above its limit too long although the regulator had lowered the feed (E: "
     "to its minimum; A: in roughing, 1.5 times the set force for 50 ms by default): the feed is "
     "held (A: the slide's valve is shut)."},
    {Reason::ToolBreakage, "tool_breakage", true, "A E",
     "The force jumped or collapsed within a few milliseconds in a cut, as when the tool "
     "breaks: the feed is held (A: in roughing, a fall of 0.6 times the set force within 10 ms "
     "by default; the slide's valve is shut)."},
    {Reason::ToolDataChanged, "tool_data_changed", true, "E",
     "The tool's number, offsets or table row changed inside a feed move: the feed is held."},
    {Reason::AirCut, "air_cut", false, "E",
     "The tool is not in the cut: the feed runs at the air feed."},
    {Reason::Engaged, "engaged", false, "E",
     "The tool has just entered the cut: the feed dropped at once to the entry feed (never above "
     "the programmed feed) and the regulator starts from there."},
    {Reason::NotInFeedBlock, "not_in_feed_block", false, "E",
     "A rapid or another move that does not cut: adaptive control is inactive."},
    {Reason::SpindleSpeedLimit, "spindle_speed_limit", false, "E",
     "The speed command is clamped to the spindle's speed range."},
    {Reason::SpindlePowerLimit, "spindle_power_limit", false, "E",
     "The speed command is lowered so that the cut stays within the spindle's power."},
    {Reason::ModulationEngaged, "modulation_engaged", false, "B",
     "Vibration above the dead zone: a modulated feed is formed and running."},
    {Reason::ModulationReleased, "modulation_released", false, "B",
     "The modulation stopped: the vibration fell below the dead zone, or the block ended."},
    {Reason::ModulationLimited, "modulation_limited", false, "B",
     "Quenching the vibration needs more feed span than the limits allow: the modulation runs at "
     "its limits."},
    {Reason::ModulationProgrammed, "modulation_programmed", false, "B",
     "The NC block's own modulation (S_min, dS, dl, n_s) is running."},
    {Reason::ModulationNoForce, "modulation_no_force", false, "B",
     "Vibration is seen but there is no cutting power or speed to size the modulation: no plan "
     "is made."},
    {Reason::GaugeBackstop, "gauge_backstop", true, "D",
     "The gauge's relay did not end the cut, the backstop position did: check the gauge."},
    {Reason::GaugeStep, "gauge_step", false, "D",
     "The gauge's signal crossed a threshold and, one relay response later, its command "
     "operates: rough to fine feed, or fine feed to spark-out."},
    {Reason::GaugeSize, "gauge_size", false, "D",
     "The gauge's signal crossed the size threshold and its relay operated: the cut ends at "
     "size."},
    {Reason::GaugeSignalLost, "gauge_signal_lost", true, "D",
     "The gauge's generator gave no signal for a whole supply period (an open wire, a probe that "
     "does not oscillate): the feed is held until the gauge is re-armed."},
    {Reason::GaugeUnreachable, "gauge_unreachable", false, "D",
     "The next threshold is above the signal of the free probe, the most the gauge can read: it "
     "can never trip, and the cut will end at the backstop."},
    // New rows go here, at the end: a reason's operation-log bit is its row's position, and the
    // logs already written keep their meaning.
    {Reason::StockAhead, "stock_ahead", false, "E",
     "The stock model sees the depth of cut rise ahead of the tool (a step, a collar, the blank "
     "coming into reach): the feed is lowered before the tool gets there, to what the new depth "
     "takes at the limit."},
    {Reason::SlideOff, "slide_off", false, "A",
     "The programming device has switched the feed slide off: the pulse valve is held shut and "
     "the slide stands."},
    {Reason::ModulationNoIdle, "modulation_no_idle", false, "B",
     "Vibration is seen but no idle power is stored yet (no idle block has run, no idle table): "
     "the motor's whole power would be taken for cutting power, so no modulation is planned."},
    {Reason::GaugeNoRoundSurface, "gauge_no_round_surface", true, "D",
     "The gauge bridges the interruptions (keyways, flats) with the round surface read before "
     "each, but they come too close together for the probe to settle and read it whole between "
     "them (the spindle too fast for them and their guard): the size cannot be read, so the feed "
     "is held until the gauge is re-armed."},
    {Reason::PowerAccelerationUnknown, "power_acceleration_unknown", false, "E",
     "The spindle changes speed in a cut and its inertia is not learned yet, so the power that "
     "accelerates it cannot be told from the cutting power: the feed may fall but not rise until "
     "a revolution after the speed settles."},
};
inline constexpr int kReasonCount = static_cast<int>(sizeof(kReasons) / sizeof(kReasons[0]));
// The operation log ORs reason_bit() of every reason seen into one 32-bit word.
static_assert(kReasonCount <= 32, "a reason's bit must fit the operation log's 32-bit mask");

// The reason's position in kReasons (its bit in the operation log); -1 for a code not listed.
constexpr int reason_index(Reason r) noexcept {
  for (int i = 0; i < kReasonCount; ++i)
    if (kReasons[i].code == r) return i;
  return -1;
}

// The operation log's bit of a reason: 1 << its position in kReasons (0 for a code not listed).
constexpr std::uint32_t reason_bit(Reason r) noexcept {
  const int i = reason_index(r);
  return i < 0 ? 0u : std::uint32_t{1} << i;
}

constexpr std::string_view reason_name(Reason r) noexcept {
  const int i = reason_index(r);
  return i < 0 ? std::string_view("unknown") : kReasons[i].name;
}

constexpr bool is_alarm(Reason r) noexcept {
  const int i = reason_index(r);
  return i >= 0 && kReasons[i].alarm;
}

}  // namespace lathectl::control
