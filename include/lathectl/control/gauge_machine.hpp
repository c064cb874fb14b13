#pragma once
// System D's machine side: what a lathe runs between the vibro-contact transducer's generator
// and the machine's feed, in one object that the simulated study (`lathectl run`) and the
// LinuxCNC component lathectl_gauge both run. Seed 003, (13)-(14) and (23):
//
//   rectifier   g = |u|, u the generator's signal (13)
//   filter      S from g: first order T_f·S' + S = g (14); second order (two lags T_f/2); or
//               synchronous (the mean over T_w, the even number of supply periods nearest 2·T_f)
//               — GaugeFilter, the same code the transducer model (sensors/) uses
//   thresholds  a sequence S_1 < S_2 < … each with its command (rough → fine → spark-out →
//               size): threshold i trips at the first upward crossing of S_i once the relay is
//               armed (interpolated between samples), and its command operates one relay
//               response time t_r later. The last step's command ends the cut (size). A
//               crossing of a later threshold trips the earlier ones not yet tripped with it
//               (the signal was above them when the relay armed: a short allowance).
//   backstop    the programmed limit position: the cut ends there whatever the gauge says, with
//               an alarm (a relay that never tripped, or tripped too late).
//   checks      signal lost: no sample of the rectified signal at signal_lost_V for a whole
//               supply period (two periods of the probe's 2ω, its peak four times) — the
//               generator's wire is open or the probe does not oscillate — holds the feed with an
//               alarm; a NaN or infinite sample, at once. A threshold above the free probe's signal (the most S can ever read) can
//               never trip: reported from the start, so the backstop's alarm is expected.
//
// Interrupted surfaces (a keyway, flats): while an interruption passes under the probe the
// probe drops into the gap or onto the flat and its amplitude reads a smaller size — a trip on a
// gap, a flat read as size. The machine knows where they are (the part's drawing and the
// spindle's angle): Input::gate is true while one is under the probe, and for gate_guard_s after
// it (the probe rings as it meets the round surface again) the samples still are not the size.
// Those samples are bridged: the filter is fed the last two supply periods of the rectified
// signal read on the round surface, replayed in phase — the period of ω/2, so every component
// the signal carries (the probe's 2ω, and ω, ω/2 when it period-doubles) continues unbroken and
// the synchronous filter's nulls hold; replaying one 2ω period instead left a finished size
// swinging by ±0.7 µm with the bridge's length, period 20 ms. The size the filter sees is then
// that of up to two supply periods plus the bridge's length ago (bridge_lag_s: the mean of that
// delay, for (23)).
//
// A bridge replays what the round surface gave just before it, so it needs, between two
// interruptions, the probe settled on the round surface (the guard) and then two supply periods
// read whole. Flats showed what happens without: two flats at 600 rpm come every 50 ms, a flat
// 100 µm deep spans 4.5 ms, and the probe, a resonator (Q ≈ 10: it rings ~30 ms) that the flat's
// deeper swing and the hard landing after it throw out of step, swings short of the part for
// cycles after; a guard that covers that leaves less than the 40 ms the replay needs, so the ring
// replays what it kept from laps before (the replayed sample 52–89 ms old where bridge_lag_s
// assumes 40, as the guard goes 10 → 30 ms) and samples of the disturbed probe: the part ended
// anywhere from the backstop (−10 µm) to +16.8 µm, jumping with the guard. The machine now says
// so: a bridge that begins before the ring has been written whole since the last one latches
// gauge_no_round_surface (the feed held) once armed — the spindle turns too fast for the
// interruptions and their guard; the scenario's check refuses such a part beforehand.
//
// A per-revolution peak-hold (the least amplitude over a revolution: the round surface read as
// the largest size) is not right for this transducer: the probe's short swings after a flat read
// smaller than the round surface's (measured: the hold ended a part with 100 µm flats at the
// backstop). The angle tells which samples the round surface gave; the amplitude does not.
//
// The relay arms arm_after_s after a (re)arm: the filter has settled on the contact by then (a
// fall of S through a threshold as the probe first touches is not a trip).
// Real-time: configure() allocates and may throw core::ParameterError naming its own parameter;
// update() never allocates, throws, locks or logs.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "lathectl/control/types.hpp"
#include "lathectl/sensors/gauge_filter.hpp"

namespace lathectl::control {

class GaugeMachine {
 public:
  static constexpr std::size_t kMaxSteps = 8;
  // The command a step gives the machine; its value is what the HAL component writes to the
  // step pin (motion.analog-in, read by M66 E-).
  enum class Command : std::int32_t { Rough = 0, Fine = 1, SparkOut = 2, Size = 3 };
  struct Step {
    bool operator==(const Step&) const = default;
    double threshold_V = 0.0;
    Command command = Command::Size;
  };
  struct Params {
    bool operator==(const Params&) const = default;
    double period_s = 5e-5;  // the sample period of the generator's signal
    sensors::GaugeFilter::Params filter;
    std::vector<Step> steps;  // 1 … kMaxSteps, thresholds rising; the last one's command: Size
    double relay_response_s = 0.02;  // t_r
    double arm_after_s = 0.5;        // after a (re)arm; ≥ 0
    // The limit position: the cut ends when Input::position_m ≤ it (−∞: none).
    double backstop_m = -std::numeric_limits<double>::infinity();
    // The filtered signal of the free probe (no contact): the most S reaches. ∞: unknown.
    double free_signal_V = std::numeric_limits<double>::infinity();
    // No sample of the rectified signal at this level for a supply period: lost (0: off).
    double signal_lost_V = 0.0;
    // Where the filter starts at reset (the free probe's signal, the transducer at rest).
    double initial_signal_V = 0.0;
    // Samples still bridged after Input::gate falls (the probe's recovery on the round surface).
    double gate_guard_s = 0.0;
  };
  // The mean delay bridging adds to the size the filter sees, over a revolution of `period_rev_s`
  // with `count` bridges of `bridge_s` each (interruption and guard): within a bridge the sample
  // fed is the one k·P before (P = 2/supply the replayed length, k = 1 + floor(s/P) at s into
  // it; P itself for a bridge shorter than P), for count·bridge_s of the revolution.
  [[nodiscard]] static double bridge_lag_s(double bridge_s, double count, double period_rev_s,
                                           double supply_Hz) noexcept;
  struct Input {
    double generator_V = 0.0;  // u
    // The controlled size's position on the same scale as backstop_m (the size left to remove
    // in the study, the infeed axis' position on a machine).
    double position_m = std::numeric_limits<double>::infinity();
    bool rearm = false;  // rising edge: a new part (steps back to rough, alarms cleared)
    bool gate = false;   // an interruption (keyway, flat) is under the probe: bridge the sample
  };
  struct Output {
    double signal_V = 0.0;  // S
    std::int32_t step = 0;  // how many steps' commands have operated
    Command command = Command::Rough;
    bool armed = false;
    bool tripped = false;  // a threshold was crossed in this sample
    // The crossing's time (interpolated between samples, from the last (re)arm) of the last
    // threshold that tripped; NaN before any.
    double trip_time_s = std::numeric_limits<double>::quiet_NaN();
    std::int32_t tripped_steps = 0;  // thresholds crossed (their commands pending or operated)
    bool size = false;      // the last step's command (size) has operated
    bool backstop = false;  // the cut ended at the backstop
    bool stop = false;      // the cut must end now: size, backstop or an alarm
    bool alarm = false;     // latched until a rearm
    bool unreachable = false;  // the next threshold is above what the free probe reads
    double next_threshold_V = std::numeric_limits<double>::quiet_NaN();
    double time_s = 0.0;  // since the last (re)arm, after this sample
    bool bridged = false;  // this sample was bridged (gate or its guard)
    Reason reason = Reason::None;
  };

  void configure(const Params& p);  // throws core::ParameterError
  void reset() noexcept;            // a new part: the filter at its initial signal
  void update(const Input& in) noexcept;
  [[nodiscard]] const Output& output() const noexcept { return out_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  void rearm() noexcept;
  void latch(Reason r) noexcept;
  // update()'s phases (gauge_machine.cpp).
  double bridge_interruption(const Input& in, double g) noexcept;
  void cross_thresholds(double s) noexcept;
  void operate_relay() noexcept;
  Params p_{};
  sensors::GaugeFilter filter_;
  Output out_{};
  double t_ = 0.0;       // since the last (re)arm, before the current sample
  double prev_ = 0.0;    // S of the last sample
  double trip_at_[kMaxSteps]{};  // when each tripped step's command operates
  std::size_t quiet_n_ = 0;  // samples since |u| last reached signal_lost_V
  std::size_t window_n_ = 1;  // samples in a supply period
  bool last_rearm_ = false;
  // The last two supply periods of |u| on the round surface (configure() sizes it), where the next
  // sample goes (or, bridging, the next one replayed), how many it holds, the guard left.
  std::vector<double> cycle_;
  std::size_t cycle_pos_ = 0, cycle_n_ = 0;
  double guard_left_s_ = 0.0;
  std::size_t round_n_ = 0;  // samples written to the ring since the last bridge
  bool bridging_ = false;
};

}  // namespace lathectl::control
