// lathectl_plant — the cutting process of a system-E scenario as a HAL component, so the
// adaptive loop closes inside LinuxCNC on a simulated machine. A thin wrapper over
// sim::LathePlant (cutting model, stock, disturbances and force sensor of the library).
//
//   loadrt lathectl_plant scenario=PATH [z_origin_mm=0] [cell_mm=0.01]
//   addf lathectl-plant servo-thread
//
// Pins (prefix lathectl-plant.): in x-pos, z-pos [mm], spindle-rpm, enable; out force (the sensor's
// sample, N or W), force-true, pz, py [N], cut-power [W], depth [mm], feed-per-rev [mm/rev],
// cutting-speed [m/min], strength-factor, in-contact, time-in-cut [s], update-ns,
// update-ns-max [ns]. See lathectl_plant(9).

#include <cmath>
#include <memory>

#include "lathectl/sim/lathe_plant.hpp"
#include "lathectl_hal.hpp"
#include "systems/e_adaptive/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl cutting-process plant (system-E scenario) for LinuxCNC");
MODULE_LICENSE("GPL");

static char* scenario = nullptr;
RTAPI_MP_STRING(scenario,
                "system-E scenario file (TOML): material, tool, stock, disturbances, sensor");
static char* z_origin_mm = nullptr;
RTAPI_MP_STRING(z_origin_mm, "machine z [mm] of the stock's z = 0 (the part lies toward -z)");
static char* cell_mm = nullptr;
RTAPI_MP_STRING(cell_mm, "workpiece grid along z [mm], default 0.01");

namespace {

constexpr const char* kName = "lathectl_plant";
constexpr const char* kPrefix = "lathectl-plant";

struct Pins {
  hal_float_t* x_pos;
  hal_float_t* z_pos;
  hal_float_t* rpm;
  hal_bit_t* enable;
  hal_float_t* force;
  hal_float_t* force_true;
  hal_float_t* pz;
  hal_float_t* py;
  hal_float_t* power;
  hal_float_t* depth;
  hal_float_t* feed;
  hal_float_t* speed;
  hal_float_t* strength;
  hal_bit_t* contact;
  hal_float_t* t_cut;
  hal_s32_t* update_ns;
  hal_s32_t* update_ns_max;
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<lathectl::sim::LathePlant> plant;
lathectl::hal::UpdateTimer timer;

void update(void*, long period_ns) {
  timer.start();
  lathectl::sim::LathePlant::Input in;
  // Disabled (e.g. before homing, positions mean nothing): no position, nothing is cut; the
  // sensor keeps reading (noise), as a live dynamometer does.
  const bool on = *pins->enable;
  in.x_mm = on ? *pins->x_pos : std::nan("");
  in.z_mm = on ? *pins->z_pos : std::nan("");
  in.rpm = *pins->rpm;
  lathectl::sim::LathePlant::Output out;
  plant->step(in, static_cast<double>(period_ns) * 1e-9, out);
  *pins->force = out.force_measured;
  *pins->force_true = out.force_parameter;
  *pins->pz = out.Pz_N;
  *pins->py = out.Py_N;
  *pins->power = out.cut_power_W;
  *pins->depth = out.depth_mm;
  *pins->feed = out.feed_per_rev_mm;
  *pins->speed = out.speed_m_per_min;
  *pins->strength = out.strength_factor;
  *pins->contact = out.in_contact;
  *pins->t_cut = out.time_in_cut_s;
  *pins->update_ns = timer.stop();
  *pins->update_ns_max = timer.max();
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  comp_id = hal_init(kName);
  if (comp_id < 0) return comp_id;
  return lathectl::hal::guarded_load(kName, comp_id, [] {
    using lathectl::hal::pin;
    namespace e_adaptive = lathectl::systems::e_adaptive;
    const auto sc = lathectl::hal::load_system(scenario, e_adaptive::kReadSection);
    lathectl::sim::LathePlant::Params p;
    p.z_origin_mm = lathectl::hal::number_param(z_origin_mm, "z_origin_mm", 0.0);
    p.cell_mm = lathectl::hal::number_param(cell_mm, "cell_mm", 0.01);
    auto model = std::make_unique<lathectl::sim::LathePlant>();
    model->configure(sc.get<e_adaptive::Settings>().rig, p);
    pins = lathectl::hal::allocate_pins<Pins>();
    pin(&pins->x_pos, HAL_IN, comp_id, kPrefix, "x-pos");
    pin(&pins->z_pos, HAL_IN, comp_id, kPrefix, "z-pos");
    pin(&pins->rpm, HAL_IN, comp_id, kPrefix, "spindle-rpm");
    pin(&pins->enable, HAL_IN, comp_id, kPrefix, "enable");
    pin(&pins->force, HAL_OUT, comp_id, kPrefix, "force");
    pin(&pins->force_true, HAL_OUT, comp_id, kPrefix, "force-true");
    pin(&pins->pz, HAL_OUT, comp_id, kPrefix, "pz");
    pin(&pins->py, HAL_OUT, comp_id, kPrefix, "py");
    pin(&pins->power, HAL_OUT, comp_id, kPrefix, "cut-power");
    pin(&pins->depth, HAL_OUT, comp_id, kPrefix, "depth");
    pin(&pins->feed, HAL_OUT, comp_id, kPrefix, "feed-per-rev");
    pin(&pins->speed, HAL_OUT, comp_id, kPrefix, "cutting-speed");
    pin(&pins->strength, HAL_OUT, comp_id, kPrefix, "strength-factor");
    pin(&pins->contact, HAL_OUT, comp_id, kPrefix, "in-contact");
    pin(&pins->t_cut, HAL_OUT, comp_id, kPrefix, "time-in-cut");
    pin(&pins->update_ns, HAL_OUT, comp_id, kPrefix, "update-ns");
    pin(&pins->update_ns_max, HAL_OUT, comp_id, kPrefix, "update-ns-max");
    plant = std::move(model);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  plant.reset();
}
