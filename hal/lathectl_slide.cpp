// lathectl_slide — system A's machine side as a HAL component: seed 000's pulse-regulated hydraulic
// feed slide (the inductive sensor, the AIM or FIM controller, finishing and roughing, the sensor
// checks, roughing's overload and breakage alarms), control::SlideMachine, the same object
// `lathectl run`'s rig A runs. The component maps pins to the machine's Input and Output, and
// forms the spool's pulse train.
//
//   loadrt lathectl_slide scenario=PATH [period_ns=1000000] [base_ns=100000]
//   addf lathectl-slide servo-thread          the controller, every control period (or in the
//                                             base thread: every k-th call, k = period / base)
//   addf lathectl-slide.pulses base-thread    the spool's pulse train
//
// The sensor: sensor-in is the analog input's raw value; U_D = sensor-in·sensor-gain +
// sensor-offset [V] (the input's calibration, pins); the scenario's sensor gives K_UP and U_0.
// AIM: slot-cmd [mm] and eccentric-pos-cmd [rad], the eccentric's angle for that slot on the
// scenario's profile — the position command for the eccentric's motor, closed by its drive (or
// by a LinuxCNC pid on eccentric-pos-fb). FIM: the pulse frequency follows the controller.
// The pulse train is formed here, in the base thread, rather than by pwmgen or stepgen: pwmgen's
// frequency is a parameter (not a pin) and FIM moves it every control period; stepgen would do
// (velocity → frequency, steplen → Δt) but cannot be told to shut the valve at once in the middle
// of a pulse (a sensor alarm in roughing) nor measures its own edges. Its resolution is one base
// period: the width is Δt rounded to base periods, and a phase accumulator keeps the mean
// frequency exact; the measured edges (rtapi_get_time) give the timing jitter on pins.
// The programming device (LinuxCNC's NC program): enable ← M64/M65 P0, roughing ← M64/M65 P1,
// reset ← M64 P2 (rising edge), feed-set [mm/min] ← M68 E0, force-set [N] ← M68 E1 (≤ 0: the
// scenario's), position [mm]: the slide's travel for the scenario's laws along it. Pins:
// lathectl_slide(9).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include "lathectl/control/slide_machine.hpp"
#include "lathectl/core/parameter_error.hpp"
#include "lathectl/drives/eccentric_drive.hpp"
#include "lathectl/sim/config_error.hpp"
#include "lathectl_hal.hpp"
#include "pins/slide.hpp"
#include "systems/a_pulse_feed/machine_params.hpp"
#include "systems/a_pulse_feed/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-A pulse-regulated feed slide (machine side) for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario, "system-A scenario file (TOML): regulator, slide, sensor, controller");
LATHECTL_HAL_PARAM(period_ns,
                   "period of the thread lathectl-slide runs in [ns], default 1000000; "
                   "controller.period_ms must be a whole number of it");
LATHECTL_HAL_PARAM(base_ns, "period of the base thread [ns]: the pulse train's, default 100000");

namespace {

constexpr const char* kName = "lathectl_slide";
constexpr const char* kPrefix = "lathectl-slide";
using lathectl::control::SlideMachine;

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_SLIDE_PINS)
  lathectl::hal::MeterPins meter;
};

struct State {
  SlideMachine machine;
  lathectl::drives::EccentricDrive eccentric;  // the slot → angle profile of the scenario's
  bool aim = true;
  long period = 1000000;
  long every = 1;  // thread calls per control period
  long calls = 0;
  long base = 100000;
  double width_s = 0.005;
  double default_feed = 0.0, default_force = 0.0;
  // Shared with the base thread: what the pulse train must do.
  std::atomic<double> frequency{0.0};
  std::atomic<bool> pulsing{false};
  // The pulse train (base thread only).
  double phase = 0.0;
  long on_left = 0;  // base periods left of the pulse in progress
  long width_ticks = 1;
  long long t_last = 0, ticks_since_rise = 0;
  long long last_rise = -1;  // time of the last rising edge
  double width_sum = 0.0, period_sum = 0.0, jitter_sum = 0.0;
  long long widths = 0, periods = 0, jitters = 0;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::Meter meter;

void update(void*, long period) {
  Pins& p = *pins;
  State& s = *st;
  if (!meter.begin(p.meter, period, s.period)) {  // configured for another control period
    s.pulsing.store(false);
    return;
  }
  if (s.calls++ % s.every != 0) {
    meter.skip(p.meter);
    return;
  }
  SlideMachine::Input in;
  p.read_pins(in, s.machine.output());  // the table's copies (pins/slide.hpp)
  in.sensor_V = *p.sensor_in * *p.sensor_gain + *p.sensor_offset;
  in.mode = *p.roughing ? SlideMachine::Mode::Roughing : SlideMachine::Mode::Finishing;
  in.feed_m_per_s = *p.feed_set > 0.0 ? *p.feed_set * 1e-3 / 60.0 : s.default_feed;
  in.force_set_N = *p.force_set > 0.0 ? *p.force_set : s.default_force;
  in.position_m = *p.position * 1e-3;
  s.machine.update(in);
  const auto& o = s.machine.output();
  p.write_pins(in, o);
  *p.sensor_V = in.sensor_V;
  *p.slot_cmd = o.slot_m * 1e3;
  if (s.aim) *p.eccentric_pos_cmd = s.eccentric.angle_of(o.slot_m);
  *p.feed_cmd = o.feed_cmd_m_per_s * 60e3;
  *p.feed_set_out = o.feed_set_m_per_s * 60e3;
  *p.roughing_out = o.mode == SlideMachine::Mode::Roughing;
  s.frequency.store(o.frequency_Hz);
  s.pulsing.store(o.pulses);
  meter.end(p.meter);
}

// The spool's pulse train: a pulse of width_ticks base periods starts whenever the phase
// (advanced by f·base each period) passes a whole number. Shut at once when the machine stops
// pulsing. Measures its own edges with the RTAPI clock.
void pulses(void*, long period) {
  Pins& p = *pins;
  State& s = *st;
  const long long now = rtapi_get_time();
  if (s.t_last != 0) {
    const long long jitter = std::llabs(now - s.t_last - period);
    if (jitter > *p.base_jitter_max_ns) *p.base_jitter_max_ns = static_cast<std::int32_t>(jitter);
    s.jitter_sum += static_cast<double>(jitter);
    *p.base_jitter_mean_ns = s.jitter_sum / static_cast<double>(++s.jitters);
  }
  s.t_last = now;
  const bool pulsing = s.pulsing.load();
  const double f = s.frequency.load();
  const bool was_on = *p.valve;
  bool on = false;
  if (pulsing && f > 0.0) {
    s.phase += f * static_cast<double>(period) * 1e-9;
    if (s.phase >= 1.0) {
      s.phase -= std::floor(s.phase);
      s.on_left = s.width_ticks;
      // A rising edge: the interval from the last one against the programmed whole number of
      // base periods (the accumulator's), measured on the RTAPI clock.
      if (s.last_rise >= 0) {
        const long long programmed = s.ticks_since_rise * period;
        const long long err = std::llabs(now - s.last_rise - programmed);
        if (err > *p.period_error_max_ns) *p.period_error_max_ns = static_cast<std::int32_t>(err);
        s.period_sum += static_cast<double>(err);
        *p.period_error_mean_ns = s.period_sum / static_cast<double>(++s.periods);
      }
      s.last_rise = now;
      s.ticks_since_rise = 0;
      *p.pulses = *p.pulses + 1;
    }
    on = s.on_left > 0;
    if (s.on_left > 0) --s.on_left;
  } else {
    s.on_left = 0;
    s.phase = 0.0;
    s.last_rise = -1;
  }
  ++s.ticks_since_rise;
  if (was_on && !on && s.last_rise >= 0 && pulsing) {  // a falling edge of a whole pulse
    const long long err = std::llabs(now - s.last_rise - static_cast<long long>(s.width_s * 1e9));
    if (err > *p.width_error_max_ns) *p.width_error_max_ns = static_cast<std::int32_t>(err);
    s.width_sum += static_cast<double>(err);
    *p.width_error_mean_ns = s.width_sum / static_cast<double>(++s.widths);
  }
  *p.valve = on;
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    using lathectl::hal::Error;
    using lathectl::hal::number_param;
    namespace a = lathectl::systems::a_pulse_feed;
    const auto sc = lathectl::hal::load_system(scenario, a::kReadSection);
    const auto& cfg = sc.get<a::Settings>().rig;
    // The machine's parameters as every host derives them from the scenario (regulator gain,
    // leakage and friction estimates, compliance, sensor K_UP; a pulsed regulator under AIM or
    // FIM): a::machine_params, which rig A calls too.
    lathectl::control::SlideMachine::Params mp;
    double start_force = 0.0;
    try {
      mp = a::machine_params(cfg, a::Host{.machine_io = true});
      start_force = a::nominal_force_N(cfg);
    } catch (const lathectl::sim::ConfigError& e) {
      throw Error(std::string(scenario) + ": " + e.key() + ": " + e.what());
    }
    auto state = std::make_unique<State>();
    const double period = number_param(period_ns, "period_ns", 1e6);
    const double base = number_param(base_ns, "base_ns", 1e5);
    if (!(base >= 1e4 && base <= 1e6)) throw Error("module parameter base_ns: expected 1e4 … 1e6");
    // The controller runs every k-th call: k = controller.period_ms / the thread's period, a
    // whole number (1 in the servo thread; 10 in a 100 µs base thread for a 1 ms controller,
    // which keeps it in step with a plant in the same thread as the rig does).
    const double k = mp.controller.period_s / (period * 1e-9);
    if (!(std::abs(k - std::round(k)) < 1e-6 && std::round(k) >= 1.0))
      throw Error(std::string(scenario) + ": controller.period_ms " +
                  std::to_string(mp.controller.period_s * 1e3) +
                  " is not a whole number of the thread's periods (period_ns=" +
                  std::to_string(period) + ")");
    state->every = std::lround(k);
    state->period = std::lround(period);
    state->base = std::lround(base);
    try {
      state->machine.configure(mp);
    } catch (const lathectl::core::ParameterError& e) {
      throw Error(std::string(scenario) + ": controller " + e.parameter() + ": " + e.what());
    }
    state->machine.start(start_force);
    state->aim = mp.controller.modulation == SlideMachine::Modulation::Amplitude;
    if (state->aim) state->eccentric.configure(cfg.eccentric);
    state->width_s = mp.controller.pulse_width_s;
    state->width_ticks = std::max(1L, std::lround(mp.controller.pulse_width_s * 1e9 / base));
    state->default_feed = mp.controller.feed_m_per_s;
    state->default_force = mp.controller.force_set_N;
    Pins& p = lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    *p.sensor_gain = 1.0;
    *p.pulse_width = mp.controller.pulse_width_s;
    *p.roughing = mp.controller.mode == SlideMachine::Mode::Roughing;
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
    lathectl::hal::check(hal_export_funct("lathectl-slide.pulses", pulses, nullptr, 1, 0, comp_id),
                         "hal_export_funct pulses");
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
