// lathectl_gauge_plant — system D's simulated machine as a HAL component: the part's size under
// the infeed and seed 003's vibro-contact transducer on it, so LinuxCNC's simulated lathe
// exercises lathectl_gauge as the study's parts exercise control::GaugeMachine.
//
//   loadrt lathectl_gauge_plant scenario=PATH size_x_mm=X [period_ns=100000]
//                               [wear_um_per_part=0] [seed=N]
//   addf lathectl-gauge-plant base-thread
//
// The part: loaded (load's rising edge) with the scenario's allowance above its target; the tool
// at machine X removes what lies beyond it, r = min(r, X + w) (radius; w the tool's wear, grown
// by wear_um_per_part at every load). The controlled size the gauge sees is
// x = (r − size_x_mm)·1e-3 + target, so x = target when the tool stands at size_x_mm. The
// disturbance ξ (the scenario's D = σ², R(τ) = D·e^{−β|τ|}: stationary Ornstein–Uhlenbeck, exact
// per sub-step) is drawn anew for every part from its own stream (seed, part): it moves the
// surface the probe touches, not the part. The transducer (sensors::VibroContactGauge, the full
// electromechanical model (5)–(12)) is stepped at the scenario's run.step_s, period/step_s
// sub-steps a call, and gives its generator's signal u (the gauge's input; it rectifies and
// filters it itself). Before the first load, and with break-wire, the probe has no part or no
// wire: no contact, or u = 0. An interrupted part (the scenario's [interruption]: keyways or
// flats): it turns with the spindle (spindle-revs, LinuxCNC's spindle.0.revs, extrapolated between
// the servo thread's updates), each part chucked at its own random angle (part-angle-deg, from
// its stream: where its first interruption's middle is at revolution 0), and the probe touches
// x + ξ − the depth under it. Pins: lathectl_gauge_plant(9).

#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>

#include "lathectl/dynamics/ornstein_uhlenbeck.hpp"
#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "lathectl_hal.hpp"
#include "pins/gauge_plant.hpp"
#include "systems/d_gauging/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION(
    "lathectl system-D plant: part size under the infeed and vibro-contact transducer");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario, "system-D scenario file (TOML): process, transducer");
LATHECTL_HAL_PARAM(size_x_mm, "machine X [mm] of the tool when the part is at its target size");
LATHECTL_HAL_PARAM(period_ns, "period of the thread this runs in [ns], default 100000");
LATHECTL_HAL_PARAM(wear_um_per_part, "tool wear per part [um], default 0");
LATHECTL_HAL_PARAM(seed, "the disturbance's seed, default the scenario's run.seed");

namespace {

constexpr const char* kName = "lathectl_gauge_plant";
constexpr const char* kPrefix = "lathectl-gauge-plant";

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_GAUGE_PLANT_PINS)
  lathectl::hal::MeterPins meter;
};

struct State {
  lathectl::sensors::VibroContactGauge gauge;
  std::mt19937_64 rng;
  std::normal_distribution<double> n01{0.0, 1.0};
  long period = 100000;
  int substeps = 5;
  double x_size_mm = 0.0, allowance_m = 0.0, target_m = 0.0;
  lathectl::dynamics::OrnsteinUhlenbeck xi;  // the size's disturbance ξ, as rig D's
  double wear_step_mm = 0.0, wear_mm = 0.0;
  double r_mm = NAN;
  std::uint64_t seed = 0;
  std::int32_t part = 0;
  bool last_load = false;
  lathectl::systems::d_gauging::Interruption interruption;
  lathectl::systems::d_gauging::SpindleAngle spindle;
  double theta0 = 0.0, sub_dt = 2e-5;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<State> st;
lathectl::hal::Meter meter;

void update(void*, long period) {
  Pins& p = *pins;
  State& s = *st;
  if (!meter.begin(p.meter, period, s.period))
    return;  // the sub-steps were sized for another thread
  const bool load = *p.load;
  if (load && !s.last_load) {  // a new blank: the last one's size is the finished one
    if (std::isfinite(s.r_mm)) *p.finished_error_um = ((s.r_mm - s.x_size_mm) * 1e-3) * 1e6;
    ++s.part;
    s.wear_mm += s.wear_step_mm;
    s.r_mm = s.x_size_mm + (s.allowance_m - s.target_m) * 1e3;
    s.rng.seed(s.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(s.part));
    s.xi.start(s.n01(s.rng));
    if (s.interruption.any())  // chucked at its own angle (drawn after ξ: ξ's stream unchanged)
      s.theta0 = std::uniform_real_distribution<double>(0.0, 2.0 * std::numbers::pi)(s.rng);
  }
  s.last_load = load;
  const double tool = *p.x_pos + s.wear_mm;
  bool cutting = false;
  double u = 0.0, x = -1e-3, under = 0.0;  // no part: the probe oscillates free
  const double revs0 = s.spindle.update(*p.spindle_revs, static_cast<double>(period) * 1e-9);
  const double rev_per_sub = s.spindle.speed_rev_per_s() * s.sub_dt;
  for (int k = 0; k < s.substeps; ++k) {
    if (std::isfinite(s.r_mm)) {
      if (tool < s.r_mm) {
        s.r_mm = tool;
        cutting = true;
      }
      x = (s.r_mm - s.x_size_mm) * 1e-3 + s.target_m;
      s.xi.step(s.n01(s.rng));
      if (s.interruption.any() && std::isfinite(revs0))
        under =
            s.interruption.depth_at(s.theta0 + 2.0 * std::numbers::pi * (revs0 + rev_per_sub * k));
    }
    u = s.gauge.step_generator(std::isfinite(s.r_mm) ? x + s.xi.value() - under : x);
  }
  *p.generator = *p.break_wire ? 0.0 : u;
  if (std::isfinite(s.r_mm)) {
    *p.size_um = x * 1e6;
    *p.error_um = (x - s.target_m) * 1e6;
    *p.radius = s.r_mm;
  }
  *p.disturbance_um = s.xi.value() * 1e6;
  *p.wear_um = s.wear_mm * 1e3;
  *p.part = s.part;
  *p.in_contact = cutting;
  *p.interruption_um = under * 1e6;
  *p.part_angle_deg = s.theta0 * 180.0 / std::numbers::pi;
  meter.end(p.meter);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    using lathectl::hal::Error;
    using lathectl::hal::number_param;
    namespace dg = lathectl::systems::d_gauging;
    const auto sc = lathectl::hal::load_system(scenario, dg::kReadSection);
    const auto& d = sc.get<dg::Settings>();
    auto state = std::make_unique<State>();
    state->x_size_mm =
        lathectl::hal::required_param(size_x_mm, "size_x_mm", "machine X at the target size");
    state->period = lathectl::hal::ranged_param(period_ns, "period_ns", 1e5, 1e4, 1e7, "1e4 … 1e7");
    const auto period = static_cast<double>(state->period);
    state->substeps = std::max(1, static_cast<int>(std::lround(period * 1e-9 / sc.run.step_s)));
    const double dt = period * 1e-9 / state->substeps;
    if (std::abs(dt - sc.run.step_s) > 1e-3 * sc.run.step_s)
      throw Error(std::string(scenario) + ": run.step_s = " + std::to_string(sc.run.step_s) +
                  " s does not divide the thread's period " + std::to_string(period * 1e-9) + " s");
    state->wear_step_mm = number_param(wear_um_per_part, "wear_um_per_part", 0.0) * 1e-3;
    state->seed =
        static_cast<std::uint64_t>(number_param(seed, "seed", static_cast<double>(sc.run.seed)));
    dg::configure_transducer(sc, state->gauge);
    const auto& pr = d.process;
    state->allowance_m = pr.allowance_m;
    state->target_m = pr.target_m;
    state->xi.configure(pr.noise_variance_m2, pr.noise_beta_per_s, dt);
    state->interruption = pr.interruption;
    state->sub_dt = dt;
    Pins& p = lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    *p.x_pos = 1e9;
    st = std::move(state);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  st.reset();
}
