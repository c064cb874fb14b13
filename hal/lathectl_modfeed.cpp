// lathectl_modfeed — seed 001's CNC module as a realtime HAL component: vibration control by
// modulated feed. A map from pins to control::ModulationMachine, the object rig B runs: the power
// chain with its idle compensation (sensor 11, switch 12, compensator 13, adder 14) and the
// planner (the staircase S_min → S_max = S_min + n_s·ΔS in steps of ΔS per path length Δl, sized
// by the quenching condition A_P ≥ c·a0·m_d·|ω_d² − ω_m²|). Detectors 19–20 (a0, ω_d) are the
// hardware in front of the CNC here (lathectl_chatter models them at the sensor's own sample
// rate, which the servo thread cannot carry): the machine takes their readings as an Input.
//
//   loadrt lathectl_modfeed scenario=PATH [ceiling=2 | output=eoffset]
//   addf lathectl-modfeed servo-thread
//   loadrt threads name1=modfeed-plan period1=10000000
//   addf lathectl-modfeed.plan modfeed-plan   (optional: the re-plan out of the servo thread)
//
// The re-plan (the quenching condition solved for the staircase; its cost: docs/linuxcnc.md) runs
// inside the servo function unless `lathectl-modfeed.plan` is added to a slower thread (created
// after the servo thread, so HAL gives it a lower priority): once that function has run, the
// servo function only posts the request and takes the finished plan in its first period after
// the planner's (control::ModulationPlanner). plans-inline / plans-taken / plans-made count which
// way the plans went (tests/hal/modfeed_test.py plan).
// Inputs: a0 and ω_d from the vibration chain's detectors (lathectl_chatter, or the machine's
// own ADC channels), the main motor's electrical power, the spindle speed, the NC block's flags
// (idle block, turret, source) and, for the programmed variant, its (S_min, ΔS, Δl, n_s).
// Output: motion.adaptive-feed, S(t)/F with F the ceiling × the mean feed (LinuxCNC clips the
// factor at 1), or with output=eoffset the flagged turret's axial axis's external offset
// (hal/config/lathectl-twin.hal). Both, the F conversion and the turret switch are the machine's
// (control::ModulationMachine::servo() and update(); its header says each); the parameters
// are systems::b_chatter::machine_params's, as rig B's.
// Pins, parameters and units: lathectl_modfeed(9).

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/control/types.hpp"
#include "lathectl/sim/config_error.hpp"
#include "lathectl_hal.hpp"
#include "pins/modfeed.hpp"
#include "systems/b_chatter/machine_params.hpp"
#include "systems/b_chatter/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl seed-001 modulated-feed module (vibration control) for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario, "system-B scenario file (TOML) whose [modulation] sets the module");
LATHECTL_HAL_PARAM(ceiling, "the program's F over the mean feed to keep (≥ 1), default 2");
LATHECTL_HAL_PARAM(output,
                   "adaptive (motion.adaptive-feed, default) or eoffset (one axis's offset)");

namespace {

using lathectl::control::ModulationMachine;
using lathectl::control::ModulationSource;
using lathectl::control::Turret;
constexpr const char* kName = "lathectl_modfeed";
constexpr const char* kPrefix = "lathectl-modfeed";

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_MODFEED_PINS)
  LATHECTL_HAL_PARAM_BLOCK(LATHECTL_MODFEED_PARAMS)
};

struct State {
  ModulationMachine machine;
  lathectl::control::ModulationPlanner planner;
  long every = 0;
  long count = 0;
  bool eoffset = false;  // output=eoffset
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::UpdateTimer timer;

// One module period's input from the pins: detectors 19–20 (outside the CNC), the motor's
// power, the spindle, the block (its F as motion gives it: the machine converts it), the
// turret and path servo() keeps.
ModulationMachine::Input module_input(const Pins& p, const ModulationMachine& m, bool feed_block) {
  const double rpm = std::abs(*p.spindle_rpm);
  ModulationMachine::Input in;
  in.external_detectors = true;
  in.a0_m = std::max(0.0, static_cast<double>(*p.a0_um)) * 1e-6;
  in.omega_d_rad_per_s = std::max(0.0, static_cast<double>(*p.omega_d_Hz)) * 2.0 * std::numbers::pi;
  in.motor_power_W = *p.spindle_power;
  in.idle_block = *p.idle_block;
  in.speed_m_per_min = 2.0 * std::numbers::pi * std::abs(*p.x_pos) * rpm / 1000.0;
  in.rpm = rpm;
  in.feed_requested = std::abs(*p.requested_vel);
  in.feed_per_rev = *p.feed_per_rev_mode;
  in.feed_rpm = rpm;
  in.turret = m.turret();
  in.path_mm[in.turret == Turret::Left ? 1 : 0] = m.path_mm();
  in.feed_block = feed_block;
  // A block that gives its plan (n_s > 0) is the programmed variant, whatever source says.
  const int src = *p.prog_n_s > 0 ? 1 : *p.source;
  in.source = src == 1   ? ModulationSource::Programmed
              : src == 2 ? ModulationSource::Automatic
                         : ModulationSource::None;
  in.programmed = {*p.prog_s_min, *p.prog_ds, *p.prog_dl, *p.prog_n_s};
  return in;
}

void update(void*, long period_ns) {
  Pins& p = *pins;
  State& s = *st;
  const double dt = static_cast<double>(period_ns) * 1e-9;
  if (s.every == 0) {  // the module's period must be a whole number of thread periods
    const double ratio = s.machine.params().module.period_s / dt;
    const long k = std::lround(ratio);
    s.every = (k < 1 || std::abs(ratio - static_cast<double>(k)) > 0.01 * ratio) ? -1 : k;
    *p.period_error = s.every < 0;
  }
  if (*p.reset_max) timer.reset();
  const bool feed_block = lathectl::control::is_feed_motion(*p.motion_type);
  // Every servo period: the turret the output acts on, the path, the external offset.
  ModulationMachine::Servo sv;
  sv.dt_s = dt;
  sv.on = s.every > 0 && *p.enable;
  sv.feed_block = feed_block;
  sv.turret = *p.turret_left ? Turret::Left : Turret::Right;
  sv.path_velocity_mm_per_s = *p.current_vel;
  sv.planned_mm[0] = *p.axis_pos_right;
  sv.planned_mm[1] = *p.axis_pos_left;
  sv.applied_offset_mm[0] = *p.axis_eoffset_right;
  sv.applied_offset_mm[1] = *p.axis_eoffset_left;
  s.machine.servo(sv);
  const auto& o = s.machine.output();
  const int t = s.machine.turret() == Turret::Left ? 1 : 0;
  if (s.eoffset) {
    *p.axis_vel = o.axis_vel_mm_per_s;
    *p.eoffset_enable_right = t == 0;
    *p.eoffset_enable_left = t == 1;
    *p.eoffset = o.offset_mm;
    *p.eoffset_counts = static_cast<std::int32_t>(
        std::lround(o.offset_mm / ModulationMachine::kOffsetResolution_mm));
  }
  if (!sv.on) {
    *p.adaptive_feed = o.factor;
    *p.engaged = 0;
    *p.feed_ratio = 1.0;
    *p.update_ns_max = timer.max();
    return;
  }
  if (s.count++ % s.every != 0) return;
  timer.start();
  s.machine.update(module_input(p, s.machine, feed_block));
  *p.feed = o.feed_mm_per_min[t];
  *p.adaptive_feed = o.factor;
  *p.feed_ratio = o.feed_ratio;
  *p.cut_power = o.cut_power_W;
  *p.engaged = o.engaged;
  *p.reason = static_cast<std::int32_t>(o.reason);
  *p.s_min = o.plan.s_min_mm_per_min;
  *p.ds = o.plan.ds_mm_per_min;
  *p.dl = o.plan.dl_mm;
  *p.n_s = o.plan.n_s;
  *p.omega_m_Hz = o.omega_m_rad_per_s / (2.0 * std::numbers::pi);
  *p.ap_required = o.force_amplitude_required_N;
  *p.ap_planned = o.force_amplitude_planned_N;
  const auto counts = s.machine.controller().plan_counts();
  *p.plans_inline = static_cast<std::int32_t>(counts.made_inline);
  *p.plans_taken = static_cast<std::int32_t>(counts.taken);
  *p.update_ns = timer.stop();
  *p.update_ns_max = timer.max();
}

// The slower thread's function: plans what the servo function asked for, if anything.
void plan(void*, long) {
  if (st && st->planner.run(st->machine.controller())) *pins->plans_made = *pins->plans_made + 1;
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    const auto sc =
        lathectl::hal::load_system(scenario, lathectl::systems::b_chatter::kReadSection);
    const auto& b = sc.get<lathectl::systems::b_chatter::Settings>().rig;
    const std::string out = output ? output : "adaptive";
    if (out != "adaptive" && out != "eoffset")
      throw lathectl::hal::Error("module parameter output=" + out +
                                 ": expected adaptive or eoffset");
    const bool eoffset = out == "eoffset";
    if (eoffset && ceiling)
      throw lathectl::hal::Error(
          "module parameter ceiling: not with output=eoffset (the program's F is the mean feed)");
    // The machine's parameters as every host derives them (b_chatter::machine_params, which rig
    // B calls too); this host's: the module period, the feed out, the ceiling.
    namespace b_chatter = lathectl::systems::b_chatter;
    b_chatter::Host host;
    host.output =
        eoffset ? ModulationMachine::FeedOutput::Offset : ModulationMachine::FeedOutput::Factor;
    host.ceiling = eoffset ? 1.0 : lathectl::hal::number_param(ceiling, "ceiling", 2.0);
    ModulationMachine::Params machine;
    try {
      machine = b_chatter::machine_params(b, host);
    } catch (const lathectl::sim::ConfigError& e) {
      throw lathectl::hal::Error("module parameter " + e.key() + ": " + e.what());
    }
    const double c = machine.ceiling;
    auto state = std::make_unique<State>();
    state->eoffset = eoffset;
    state->machine.configure(machine);
    state->machine.use_planner(&state->planner);
    Pins& p = lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    const lathectl::hal::Exporter x(comp_id, kPrefix);  // the parameters
    *p.eoffset_scale = ModulationMachine::kOffsetResolution_mm;
    *p.feed_ratio = 1.0;
    *p.adaptive_feed = 1.0 / c;
    *p.source = static_cast<std::int32_t>(b.source);
    *p.turret_left = b.turret == Turret::Left;
    *p.enable = 1;
    p.export_params(x, machine);
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
    lathectl::hal::export_update("lathectl-modfeed.plan", plan, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
