// lathectl_slide_plant — system A's simulated machine as a HAL component: rig A's plant (the
// cutting process with the scenario's disturbances, the inductive sensor, the eccentric drive,
// the pulse regulator with its spool dynamics and obliteration, the damper, the cylinder with its
// leakage), the same code `lathectl run` runs, driven by the machine's own pulse train, so that
// LinuxCNC's simulated lathe exercises lathectl_slide as the rig exercises control::SlideMachine.
//
//   loadrt lathectl_slide_plant scenario=PATH [period_ns=100000] [summary=PATH]
//   addf lathectl-slide-plant base-thread     after lathectl-slide.pulses
//
// One call is one rig step: the base period must be the scenario's run.step_s. The plant's clock
// starts at the first call with run high (the slide switched on) and stops at the scenario's
// run.duration_s (done goes high); in between it records as the rig does, and the rows feed A's
// metrics. At unload, summary=PATH receives those metrics as `lathectl run` names them in
// summary.json (feed_rate_mean_mm_per_min, feed_rate_deviation_pct, force_peak_N,
// force_final_error_pct, ...). Pins: lathectl_slide_plant(9).

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "lathectl_hal.hpp"
#include "pins/slide_plant.hpp"
#include "systems/a_pulse_feed/metrics.hpp"
#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/a_pulse_feed/study.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-A plant: cutting, sensor, pulse regulator, damper, cylinder");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario, "system-A scenario file (TOML)");
LATHECTL_HAL_PARAM(period_ns,
                   "period of the thread this runs in [ns], default 100000 (= run.step_s)");
LATHECTL_HAL_PARAM(summary, "where to write the run's metrics (JSON) at unload; default none");

namespace {

constexpr const char* kName = "lathectl_slide_plant";
constexpr const char* kPrefix = "lathectl-slide-plant";
namespace a = lathectl::systems::a_pulse_feed;

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_SLIDE_PLANT_PINS)
  lathectl::hal::MeterPins meter;
};

struct State {
  a::Rig rig;
  std::unique_ptr<a::MetricsAccumulator> acc;
  lathectl::drives::EccentricDrive eccentric;  // its profile: angle → slot
  bool aim = true;
  long period = 100000;
  std::size_t steps = 0, steps_total = 0;
  bool started = false;
  std::string summary;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::Meter meter;

void update(void*, long period) {
  Pins& p = *pins;
  State& s = *st;
  if (!meter.begin(p.meter, period, s.period)) return;
  if (!s.started && *p.run) s.started = true;
  if (s.started && s.steps < s.steps_total) {
    a::Rig::Actuation act;
    act.valve_open = *p.valve;
    act.slot_cmd_m = s.aim ? s.eccentric.slot_of(*p.eccentric_pos_cmd) : 0.0;
    act.frequency_Hz = *p.frequency;
    act.out.force_estimate_N = *p.force_estimate;
    act.out.reason = static_cast<lathectl::control::Reason>(*p.reason);
    act.out.alarm = *p.alarm;
    s.rig.actuate(act);
    s.rig.step();
    ++s.steps;
  }
  *p.done = s.steps >= s.steps_total;
  *p.sensor_out = s.rig.sensor_reading();
  *p.force = s.rig.force();
  *p.position = s.rig.position() * 1e3;
  *p.slot = s.rig.eccentric_slot() * 1e3;
  if (s.aim) *p.eccentric_pos_fb = s.eccentric.angle_of(s.rig.eccentric_slot());
  *p.plant_time = s.rig.time();
  meter.end(p.meter);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    using lathectl::hal::Error;
    using lathectl::hal::number_param;
    const auto sc = lathectl::hal::load_system(scenario, a::kReadSection);
    const auto& cfg = sc.get<a::Settings>().rig;
    auto state = std::make_unique<State>();
    const double period = number_param(period_ns, "period_ns", 1e5);
    if (std::abs(period * 1e-9 - sc.run.step_s) > 1e-12)
      throw Error(std::string(scenario) + ": run.step_s " + std::to_string(sc.run.step_s) +
                  " s is not the base period (period_ns=" + std::to_string(period) + ")");
    state->period = std::lround(period);
    state->rig.set_streamed(true, false);  // rows to the metrics only
    state->rig.set_external(true);
    try {
      state->rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
    } catch (const std::invalid_argument& e) {
      throw Error(std::string(scenario) + ": " + e.what());
    }
    state->acc = std::make_unique<a::MetricsAccumulator>(state->rig, state->rig.last_record_time());
    state->acc->set_plot(false);  // the report's plot grows with the run: not in this thread
    state->rig.attach(state->acc.get());
    state->steps_total = static_cast<std::size_t>(std::llround(sc.run.duration_s / sc.run.step_s));
    state->aim = cfg.controller_kind == a::ControllerKind::Aim;
    if (state->aim) state->eccentric.configure(cfg.eccentric);
    if (summary != nullptr) state->summary = summary;
    Pins& p = lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    *p.sensor_out = state->rig.sensor_reading();
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

// At unload (not real time): the run's metrics, as lathectl run's summary.json names them.
extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  if (st && !st->summary.empty()) {
    try {
      auto j = a::metrics_json(st->acc->result(st->rig));
      j["plant_time_s"] = st->rig.time();
      j["complete"] = st->steps >= st->steps_total;
      std::ofstream f(st->summary);
      f << j.dump(2) << "\n";
      if (!f) rtapi_print_msg(RTAPI_MSG_ERR, "%s: cannot write %s\n", kName, st->summary.c_str());
    } catch (const std::exception& e) {
      rtapi_print_msg(RTAPI_MSG_ERR, "%s: summary: %s\n", kName, e.what());
    }
  }
  st.reset();
}
