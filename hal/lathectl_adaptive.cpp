// lathectl_adaptive — the system-E adaptive controller (seed 004: force held by the feed, cutting
// speed by V_opt = V_p·(S_p/S_cur)^y_v) as a realtime HAL component. A thin wrapper: the control
// law is control::AdaptiveFeedController, the same object file the simulator links.
//
//   loadrt lathectl_adaptive scenario=PATH
//   addf lathectl-adaptive servo-thread
//
// The controller's settings come from the scenario's [controller] and [sensor] sections (the
// same file `lathectl run` reads). Its feed per revolution becomes motion.adaptive-feed as the
// ratio to the program's feed per revolution (requested velocity / spindle speed), clamped to
// [0, 1]: never negative (a negative factor runs the path backwards), never above the program.
// The cutting power the speed law limits is the one the rig computes (control::adaptive_input):
// from Pz·V, from the power sensor itself, or, with a Py sensor, from spindle-power minus the
// scenario's idle power. Pins, parameters and units: lathectl_adaptive(9).

#include <algorithm>
#include <memory>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/control/adaptive_input.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl_hal.hpp"
#include "systems/e_adaptive/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-E adaptive feed and cutting-speed controller for LinuxCNC");
MODULE_LICENSE("GPL");

static char* scenario = nullptr;
RTAPI_MP_STRING(scenario,
                "system-E scenario file (TOML) whose [controller] and [sensor] set the controller");

namespace {

using lathectl::control::AdaptiveFeedController;
constexpr const char* kName = "lathectl_adaptive";
constexpr const char* kPrefix = "lathectl-adaptive";

struct Pins {
  // inputs
  hal_float_t* force;
  hal_float_t* rpm;
  hal_float_t* rpm_programmed;
  hal_float_t* current_vel;
  hal_float_t* requested_vel;
  hal_s32_t* motion_type;
  hal_float_t* x_pos;
  hal_float_t* cutting_speed;
  hal_float_t* spindle_power;
  hal_bit_t* per_rev;
  hal_bit_t* enable;
  hal_bit_t* reset;
  // outputs
  hal_float_t* adaptive_feed;
  hal_float_t* spindle_speed_out;
  hal_float_t* spindle_override;
  hal_bit_t* feed_hold;
  hal_bit_t* alarm;
  hal_s32_t* reason;
  hal_s32_t* alarm_reason;
  hal_float_t* feed_per_rev;
  hal_float_t* speed_cmd;
  hal_float_t* speed_opt;
  hal_float_t* cut_power;
  hal_bit_t* in_cut;
  hal_bit_t* period_error;
  hal_s32_t* update_ns;
  hal_s32_t* update_ns_max;
  hal_bit_t* reset_max;
  // parameters (read-only: the scenario's settings)
  hal_float_t force_limit;
  hal_float_t feed_min;
  hal_float_t feed_max;
  hal_float_t feed_programmed;
  hal_float_t speed_programmed;
  hal_float_t control_period;
};

struct State {
  AdaptiveFeedController ctl;
  AdaptiveFeedController::Output out{};
  lathectl::cutting::ForceParameter parameter = lathectl::cutting::ForceParameter::Pz;
  lathectl::drives::SpindleDrive::Params spindle;  // its idle law
  bool speed_law = false;
  long every = 0;  // thread periods per control period (0: not yet known)
  long count = 0;
  bool last_reset = false;
  // motion.requested-vel turns to the next block's value one period before motion.motion-type
  // does (seen at a G1 → G0 change: for one period the rapid's 80 mm/s read as the G95 feed);
  // a value is used once it has held for one thread period.
  double req_prev = 0.0;
  double req_stable = 0.0;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::UpdateTimer timer;

void hold_all(Pins& p) {
  *p.adaptive_feed = 0.0;
  *p.feed_hold = 1;
  *p.alarm = 1;
  *p.spindle_speed_out = *p.rpm_programmed;
  *p.spindle_override = 1.0;
}

void update(void*, long period_ns) {
  Pins& p = *pins;
  State& s = *st;
  if (s.every == 0) {  // the control period must be a whole number of thread periods
    const double ratio = s.ctl.params().period_s * 1e9 / static_cast<double>(period_ns);
    const long k = std::lround(ratio);
    if (k < 1 || std::abs(ratio - static_cast<double>(k)) > 0.01 * ratio) {
      s.every = -1;
      *p.period_error = 1;
    } else {
      s.every = k;
    }
  }
  if (s.every < 0) {
    hold_all(p);
    return;
  }
  if (*p.reset_max) timer.reset();
  if (*p.reset && !s.last_reset) s.ctl.reset_alarm();
  s.last_reset = *p.reset;
  const double rpm_prog = *p.rpm_programmed;
  const double req_now = std::abs(*p.requested_vel);
  if (req_now == s.req_prev) s.req_stable = req_now;
  s.req_prev = req_now;
  if (s.count++ % s.every == 0) {
    timer.start();
    const bool enabled = *p.enable;
    const double rpm = std::abs(*p.rpm);
    lathectl::control::AdaptiveSignals sig;
    sig.force = *p.force;
    sig.spindle_power_W = *p.spindle_power;
    sig.idle_power_W = lathectl::drives::idle_power_W(s.spindle, rpm);
    sig.rpm = rpm;
    sig.feed_rate_mm_per_min = std::abs(*p.current_vel) * 60.0;
    // Sensor 20: a measured cutting speed when one is wired, else π·D·n at the tool's diameter.
    const double v_meas = *p.cutting_speed;
    sig.speed_m_per_min =
        v_meas > 0.0 ? v_meas : 3.14159265358979323846 * 2.0 * std::abs(*p.x_pos) * rpm / 1000.0;
    sig.feed_block = enabled && (*p.motion_type == 2 || *p.motion_type == 3);
    const auto in = lathectl::control::adaptive_input(s.parameter, sig);
    (void)s.ctl.update(in, s.out);
    *p.cut_power = in.cut_power_W;
    const auto& o = s.out;
    double factor = 1.0;
    if (in.feed_block) {
      // The program's feed per revolution: motion reports the F word itself under G95, a
      // velocity [mm/s] under G94.
      const double req = s.req_stable;
      const double prog_per_rev = *p.per_rev ? req : rpm > 0.0 ? req * 60.0 / rpm : 0.0;
      factor = o.feed_hold          ? 0.0
               : prog_per_rev > 0.0 ? std::clamp(o.feed_per_rev_mm / prog_per_rev, 0.0, 1.0)
                                    : 1.0;
    }
    const bool hold = enabled && o.feed_hold;
    *p.adaptive_feed = hold ? 0.0 : factor;
    *p.feed_hold = hold;
    *p.alarm = o.alarm;
    *p.reason = static_cast<std::int32_t>(o.reason);
    *p.alarm_reason = static_cast<std::int32_t>(o.alarm_reason);
    *p.feed_per_rev = o.feed_per_rev_mm;
    *p.speed_cmd = o.speed_m_per_min;
    *p.speed_opt = o.speed_opt_m_per_min;
    *p.in_cut = o.in_cut;
    // Seed 004's speed law drives the spindle while the program runs it; otherwise the program's
    // speed passes through.
    double rpm_out = rpm_prog;
    if (enabled && s.speed_law && rpm_prog != 0.0) rpm_out = std::copysign(o.rpm, rpm_prog);
    *p.spindle_speed_out = rpm_out;
    *p.spindle_override = rpm_prog != 0.0 ? rpm_out / rpm_prog : 1.0;
    *p.update_ns = timer.stop();
  } else if (!(*p.enable && s.speed_law)) {
    *p.spindle_speed_out = rpm_prog;  // pass program speed changes through between updates
  }
  *p.update_ns_max = timer.max();
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  comp_id = hal_init(kName);
  if (comp_id < 0) return comp_id;
  return lathectl::hal::guarded_load(kName, comp_id, [] {
    using lathectl::hal::param;
    using lathectl::hal::pin;
    namespace e_adaptive = lathectl::systems::e_adaptive;
    const auto sc = lathectl::hal::load_system(scenario, e_adaptive::kReadSection);
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    auto state = std::make_unique<State>();
    state->ctl.configure(e.controller);
    state->parameter = e.force_parameter;
    state->spindle = e.spindle;
    state->speed_law = e.controller.mode == AdaptiveFeedController::Mode::ForceFeedSpeed;
    const auto& c = e.controller;
    pins = lathectl::hal::allocate_pins<Pins>();
    Pins& p = *pins;
    pin(&p.force, HAL_IN, comp_id, kPrefix, "force");
    pin(&p.rpm, HAL_IN, comp_id, kPrefix, "spindle-rpm");
    pin(&p.rpm_programmed, HAL_IN, comp_id, kPrefix, "spindle-rpm-programmed");
    pin(&p.current_vel, HAL_IN, comp_id, kPrefix, "current-vel");
    pin(&p.requested_vel, HAL_IN, comp_id, kPrefix, "requested-vel");
    pin(&p.motion_type, HAL_IN, comp_id, kPrefix, "motion-type");
    pin(&p.x_pos, HAL_IN, comp_id, kPrefix, "x-pos");
    pin(&p.cutting_speed, HAL_IN, comp_id, kPrefix, "cutting-speed");
    pin(&p.spindle_power, HAL_IN, comp_id, kPrefix, "spindle-power");
    pin(&p.per_rev, HAL_IN, comp_id, kPrefix, "feed-per-rev-mode");
    pin(&p.enable, HAL_IN, comp_id, kPrefix, "enable");
    pin(&p.reset, HAL_IN, comp_id, kPrefix, "reset");
    pin(&p.adaptive_feed, HAL_OUT, comp_id, kPrefix, "adaptive-feed");
    pin(&p.spindle_speed_out, HAL_OUT, comp_id, kPrefix, "spindle-speed-out");
    pin(&p.spindle_override, HAL_OUT, comp_id, kPrefix, "spindle-override");
    pin(&p.feed_hold, HAL_OUT, comp_id, kPrefix, "feed-hold");
    pin(&p.alarm, HAL_OUT, comp_id, kPrefix, "alarm");
    pin(&p.reason, HAL_OUT, comp_id, kPrefix, "reason");
    pin(&p.alarm_reason, HAL_OUT, comp_id, kPrefix, "alarm-reason");
    pin(&p.feed_per_rev, HAL_OUT, comp_id, kPrefix, "feed-per-rev");
    pin(&p.speed_cmd, HAL_OUT, comp_id, kPrefix, "cutting-speed-cmd");
    pin(&p.speed_opt, HAL_OUT, comp_id, kPrefix, "cutting-speed-opt");
    pin(&p.cut_power, HAL_OUT, comp_id, kPrefix, "cut-power");
    pin(&p.in_cut, HAL_OUT, comp_id, kPrefix, "in-cut");
    pin(&p.period_error, HAL_OUT, comp_id, kPrefix, "period-error");
    pin(&p.update_ns, HAL_OUT, comp_id, kPrefix, "update-ns");
    pin(&p.update_ns_max, HAL_OUT, comp_id, kPrefix, "update-ns-max");
    pin(&p.reset_max, HAL_IN, comp_id, kPrefix, "reset-max");
    *p.adaptive_feed = 1.0;
    *p.spindle_override = 1.0;
    param(&p.force_limit, HAL_RO, comp_id, kPrefix, "force-limit", c.force_limit);
    param(&p.feed_min, HAL_RO, comp_id, kPrefix, "feed-min", c.feed_min_mm_per_rev);
    param(&p.feed_max, HAL_RO, comp_id, kPrefix, "feed-max", c.feed_max_mm_per_rev);
    param(&p.feed_programmed, HAL_RO, comp_id, kPrefix, "feed-programmed",
          c.feed_programmed_mm_per_rev);
    param(&p.speed_programmed, HAL_RO, comp_id, kPrefix, "cutting-speed-programmed",
          c.speed_programmed_m_per_min);
    param(&p.control_period, HAL_RO, comp_id, kPrefix, "control-period", c.period_s);
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
