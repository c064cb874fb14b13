// lathectl_chatter — system B's cutting process as a HAL component: the slender part between
// centres, its modes at the tools, regeneration and the tools leaving the cut
// (dynamics::TwinTurretCut: one tool, or the twin turrets of feed or depth division — the second
// turret's Z on its own pin, e.g. a second axis pair U/W beside X/Z), with the hardware of
// seed 001's measurement chain — vibration sensor 16, amplifier 17 with its dead zone, amplitude
// detector (ADC 19) and frequency detector 20 (sensors::VibrationChain) — and the main motor's
// electrical power (cutting power / efficiency + the spindle's speed-dependent idle losses).
//
//   loadrt lathectl_chatter scenario=PATH [z_origin_mm=0] [period_ns=1000000]
//   addf lathectl-chatter servo-thread
//
// Chatter at a few hundred hertz cannot be stepped at the servo period, so each call advances
// the process in sub-steps of the scenario's run.step_s, the axis position and spindle angle
// interpolated linearly between the previous call's and this one's. The part coordinate is
// z_part = z_origin_mm − z (the tool feeds toward −Z, into increasing z_part).
// Pins, parameters and units: lathectl_chatter(9).

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/dynamics/twin_turret.hpp"
#include "lathectl/sensors/vibration_chain.hpp"
#include "lathectl_hal.hpp"
#include "pins/chatter.hpp"
#include "systems/b_chatter/machine_params.hpp"
#include "systems/b_chatter/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-B chatter plant (slender part, regeneration) for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario, "system-B scenario file (TOML): part, material, cut, sensors");
LATHECTL_HAL_PARAM(z_origin_mm, "machine z [mm] of the part's z = 0 (the part lies toward -z)");
LATHECTL_HAL_PARAM(period_ns, "period of the thread this runs in [ns], default 1000000");

namespace {

constexpr const char* kName = "lathectl_chatter";
constexpr const char* kPrefix = "lathectl-chatter";

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_CHATTER_PINS)
  lathectl::hal::MeterPins meter;
};

struct State {
  lathectl::dynamics::TwinTurretCut cut;
  lathectl::sensors::VibrationChain chain;
  // Rig B's measure of the vibration (y_highpass: the sensor's high-pass on the noiseless
  // displacement, every step), for recorders comparing with `lathectl run`.
  lathectl::sensors::HighPass2 highpass;
  double z_origin = 0.0;
  long period = 1000000;
  int substeps = 50;
  int chain_every = 1;
  long count = 0;
  bool started = false;
  bool twin = false;
  double last_z = 0.0, last_z2 = 0.0, last_revs = 0.0;
  lathectl::drives::SpindleDrive::Params spindle;  // efficiency and idle law
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::Meter meter;

void update(void*, long period) {
  Pins& p = *pins;
  State& s = *st;
  if (!meter.begin(p.meter, period, s.period)) return;  // the sub-step was sized for another thread
  const double z = *p.enable ? s.z_origin - *p.z_pos : -1e9;  // disabled: far from the part
  const double z2 = !s.twin ? z : *p.enable ? s.z_origin - *p.z2_pos : -1e9;
  const double revs = *p.spindle_revs;
  if (!s.started) {
    s.last_z = z;
    s.last_z2 = z2;
    s.last_revs = revs;
    s.started = true;
  }
  const double rpm = std::abs(*p.spindle_rpm);
  double peak = 0.0;
  for (int k = 1; k <= s.substeps; ++k) {
    const double f = static_cast<double>(k) / s.substeps;
    const double zk = s.last_z + f * (z - s.last_z);
    const double theta = 2.0 * std::numbers::pi * (s.last_revs + f * (revs - s.last_revs));
    const double zz[2] = {zk, s.last_z2 + f * (z2 - s.last_z2)};
    s.cut.step(theta, rpm, zz);
    peak = std::max(peak, std::abs(s.highpass.step(s.cut.y_m())));
    if (s.count++ % s.chain_every == 0) s.chain.update(s.cut.y_m());
  }
  s.last_z = z;
  s.last_z2 = z2;
  s.last_revs = revs;
  const double pc = s.cut.power_W(rpm);
  *p.vibration_um = s.cut.y_m() * 1e6;
  *p.vibration_peak_um = peak * 1e6;
  *p.a0_um = s.chain.a0_m() * 1e6;
  *p.omega_d_Hz = s.chain.omega_d() / (2.0 * std::numbers::pi);
  *p.radial_force = s.cut.radial_N(0);
  *p.tangential_force = s.cut.tangential_N(0);
  *p.cut_power = pc;
  *p.spindle_power = pc / s.spindle.efficiency + lathectl::drives::idle_power_W(s.spindle, rpm);
  *p.chip = s.cut.cutting(0) ? s.cut.chip_mm(0) : 0.0;
  *p.depth = s.cut.cutting(0) ? s.cut.depth_mm(0) : 0.0;
  *p.in_contact = s.cut.cutting(0);
  const bool two = s.twin && s.cut.cutting(1);
  *p.radial_force2 = s.twin ? s.cut.radial_N(1) : 0.0;
  *p.chip2 = two ? s.cut.chip_mm(1) : 0.0;
  *p.depth2 = two ? s.cut.depth_mm(1) : 0.0;
  *p.in_contact2 = two;
  *p.diverged = !s.cut.sound();
  meter.end(p.meter);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    const auto sc =
        lathectl::hal::load_system(scenario, lathectl::systems::b_chatter::kReadSection);
    const auto& b = sc.get<lathectl::systems::b_chatter::Settings>().rig;
    auto state = std::make_unique<State>();
    state->twin = b.setup != lathectl::dynamics::TwinSetup::Single;
    state->z_origin = lathectl::hal::number_param(z_origin_mm, "z_origin_mm", 0.0);
    state->period = lathectl::hal::ranged_param(period_ns, "period_ns", 1e6, 1e4, 1e8, "1e4 … 1e8");
    const auto period = static_cast<double>(state->period);
    state->substeps = std::max(1, static_cast<int>(std::lround(period * 1e-9 / sc.run.step_s)));
    const double dt = period * 1e-9 / state->substeps;
    // The scenario's process (process damping included) as the rig maps it. One tool: the second
    // edge follows the first (the plant's single set-up ignores it); twin set-ups: the second
    // turret's axial positions come from z2-pos, the program places it tool2_lag_mm behind.
    auto pp = lathectl::systems::b_chatter::cut_params(b);
    if (!state->twin) {
      pp.depth_mm[1] = b.depth_mm[0];
      pp.tool2_lag_mm = 0.0;
    }
    state->cut.configure(pp, dt);
    state->chain_every = std::max(
        1, static_cast<int>(std::lround(lathectl::systems::b_chatter::kSamplePeriod_s / dt)));
    auto vib = b.vibration;
    vib.sample_period_s = dt * state->chain_every;
    state->chain.configure(vib);
    state->highpass.configure(b.vibration.highpass_Hz, dt);
    state->spindle = b.spindle;
    lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
