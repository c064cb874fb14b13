// lathectl_plant — the cutting process of a system-E scenario as a HAL component, so the
// adaptive loop closes inside LinuxCNC on a simulated machine. A thin wrapper over
// cutting::LathePlant (cutting model, stock, disturbances and force sensor of the library).
//
//   loadrt lathectl_plant scenario=PATH [z_origin_mm=0] [cell_mm=0.01] [warmup_s=120]
//                         [idle_drift=0.15] [period_ns=1000000] [tool_file=PATH]
//                         [tool_table=PATH]
//   addf lathectl-plant servo-thread
//
// Pins (hal/pins/plant.hpp; lathectl_plant(9)): the tool's position, the spindle's speed and the
// motion type in; out the sensor's force and the true one, the forces, the cutting power, the cut's
// geometry, the per-revolution force (control::PerRevolutionPeak: `lathectl run`'s
// force_peak_rev_mean_N), the stock's radius at probe-z, and the spindle drive's power
// (drives::SpindlePowerAtSpeed through the scenario's power meter, as `lathectl run` and
// `lathectl optimize` see it). tool_file (lathectl optimize's --tool-file, its reader
// io::read_tool_file): a grooving or parting tool in the spindle (pin tool-number,
// iocontrol.0.tool-number) cuts its insert's whole width in feed moves, as the optimiser predicts
// it (cutting::LathePlant::Input::insert_width_mm); any other tool cuts with the nose.
// tool_table (LinuxCNC's tool table, the INI's [EMCIO]TOOL_TABLE, in mm; its reader
// io::read_tool_table): the tool in the spindle cuts with its own nose and orientation, the
// choice lathectl optimize's prediction makes (io::tool_geometry: the tool file's nose radius,
// else the table's D/2, else the scenario's; the table's Q, else the scenario's orientation;
// the table's I and J, else the scenario's [tool] angles: the insert's straight edges).

#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "lathectl/control/per_revolution.hpp"
#include "lathectl/control/types.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/tool_file.hpp"
#include "lathectl/sensors/force_sensor.hpp"
#include "lathectl_hal.hpp"
#include "pins/plant.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/settings.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl cutting-process plant (system-E scenario) for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(scenario,
                   "system-E scenario file (TOML): material, tool, stock, disturbances, sensor");
LATHECTL_HAL_PARAM(z_origin_mm, "machine z [mm] of the stock's z = 0 (the part lies toward -z)");
LATHECTL_HAL_PARAM(cell_mm, "workpiece grid along z [mm], default 0.01");
LATHECTL_HAL_PARAM(warmup_s, "time constant of the idle power's warm-up drift [s], default 120");
LATHECTL_HAL_PARAM(break_at_s,
                   "the tool breaks after this time in cut [s] (no force from then on); "
                   "default never");
LATHECTL_HAL_PARAM(period_ns, "period of the servo thread this runs in [ns], default 1000000");
LATHECTL_HAL_PARAM(idle_drift, "extra idle power of the cold machine (fraction), default 0.15");
LATHECTL_HAL_PARAM(tool_table,
                   "LinuxCNC's tool table ([EMCIO]TOOL_TABLE, mm): the nose (D/2) and orientation "
                   "(Q) of the tool in the spindle; default none (the scenario's tool)");
LATHECTL_HAL_PARAM(tool_file,
                   "tool file (TOML [[tool]], lathectl optimize --tool-file): the insert width of "
                   "each grooving or parting tool; default none (every tool cuts with the nose)");

namespace {

constexpr const char* kName = "lathectl_plant";
constexpr const char* kPrefix = "lathectl-plant";

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_PLANT_PINS)
};

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<lathectl::cutting::LathePlant> plant;
// The spindle drive's power at LinuxCNC's speed, read through the machine's power meter: the same
// law and meter as rig E's (drives::SpindlePowerAtSpeed, e_adaptive::spindle_power_meter).
lathectl::drives::SpindlePowerAtSpeed drive;
lathectl::sensors::LaggedNoisySensor meter;
double break_at = 0.0;  // 0: never
lathectl::hal::UpdateTimer timer;
lathectl::hal::HomedGate homed_gate;
lathectl::control::PerRevolutionPeak force_rev;  // configured at load for the controller's period
double run_s = 0.0;
// (tool number, insert width [mm]) of the tool file's grooving and parting tools, read at load.
std::vector<std::pair<int, double>> plunge_tools;
// The tool file's and the tool table's tools (read at load) and the scenario's nose: the tool in
// the spindle's geometry (io::tool_geometry), set on the plant when the tool changes.
std::vector<lathectl::io::ToolSpec> file_tools;
std::vector<lathectl::io::TableTool> table_tools;
lathectl::io::ToolGeometry scenario_tool;
std::int32_t tool_in_plant = -1;

// The width of cut of the tool in the spindle in a feed move: its insert's, 0 for the nose.
double insert_width(std::int32_t tool, bool feed_move) noexcept {
  if (!feed_move) return 0.0;  // a rapid through material: the nose (as the optimiser's)
  for (const auto& [number, width] : plunge_tools)
    if (number == tool) return width;
  return 0.0;
}

void update(void*, long period_ns) {
  timer.start();
  lathectl::cutting::LathePlant::Input in;
  // Disabled (e.g. before homing, positions mean nothing): no position, nothing is cut; the
  // sensor keeps reading (noise), as a live dynamometer does.
  const bool on = homed_gate(*pins->enable, *pins->x_pos, *pins->z_pos);
  in.x_mm = on ? *pins->x_pos : std::nan("");
  in.z_mm = on ? *pins->z_pos : std::nan("");
  lathectl::cutting::LathePlant::Output out;
  pins->read_pins(in, out);  // the table's copies (pins/plant.hpp)
  if (*pins->tool_number != tool_in_plant) {  // M6: the new tool's nose, the stock stays
    tool_in_plant = *pins->tool_number;
    const auto g =
        lathectl::io::tool_geometry(file_tools, table_tools, tool_in_plant, scenario_tool);
    plant->set_tool(g.nose_radius_mm, g.orientation);
    plant->set_edges(g.front_angle_deg, g.back_angle_deg);  // its insert's edges (I, J)
  }
  const bool feed_move = lathectl::control::is_feed_motion(*pins->motion_type);
  in.insert_width_mm = insert_width(*pins->tool_number, feed_move);
  *pins->insert_width = in.insert_width_mm;
  plant->step(in, static_cast<double>(period_ns) * 1e-9, out);
  if (break_at > 0.0 && out.time_in_cut_s >= break_at) {  // a broken tool: nothing is cut
    out.force_measured = out.force_parameter = out.Pz_N = out.Py_N = out.cut_power_W = 0.0;
    out.depth_mm = 0.0;
  }
  pins->write_pins(in, out);
  {  // the drive's power pin
    const double dt = static_cast<double>(period_ns) * 1e-9;
    meter.step(dt, drive.step(dt, in.rpm, out.cut_power_W));
    *pins->idle_power = drive.idle_power_W();
    *pins->idle_drift_factor = drive.idle_factor();
    *pins->spindle_power = meter.sample();
  }
  {
    run_s += static_cast<double>(period_ns) * 1e-9;
    const bool cutting = feed_move && out.depth_mm > 0.0 && out.feed_per_rev_mm > 0.0;
    *pins->force_rev_mean =
        force_rev.push(run_s, feed_move ? out.force_parameter : 0.0, in.rpm, cutting);
    *pins->force_rev_peak = force_rev.peak();
  }
  *pins->probe_radius = plant->radius_mm(plant->stock_z_mm(*pins->probe_z));
  *pins->update_ns = timer.stop();
  *pins->update_ns_max = timer.max();
}

// The tool file and the tool table (module parameters), as lathectl optimize reads them: one
// reader each, the table filling the file's noses where it gives none and the two agreeing.
void read_tools(const lathectl::systems::e_adaptive::RigConfig& e) {
  plunge_tools.clear();
  file_tools.clear();
  table_tools.clear();
  scenario_tool = {e.cutting.nose_radius_mm, e.tool_orientation, e.tool_front_angle_deg,
                   e.tool_back_angle_deg};
  tool_in_plant = -1;
  const bool has_file = tool_file != nullptr && *tool_file != '\0';
  if (has_file) {
    lathectl::hal::require_readable(tool_file, "tool file");
    file_tools = lathectl::io::read_tool_file(lathectl::io::read_scenario_text(tool_file), tool_file);
    for (const auto& t : file_tools)
      if (t.plunge()) plunge_tools.emplace_back(t.number, t.insert_width_mm);
  }
  if (tool_table != nullptr && *tool_table != '\0') {
    lathectl::hal::require_readable(tool_table, "tool table");
    table_tools = lathectl::io::read_tool_table(lathectl::io::read_scenario_text(tool_table),
                                                tool_table);
    lathectl::io::apply_tool_table(file_tools, table_tools, has_file ? tool_file : "",
                                   tool_table);
  }
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    namespace e_adaptive = lathectl::systems::e_adaptive;
    const auto sc = lathectl::hal::load_system(scenario, e_adaptive::kReadSection);
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    read_tools(e);
    lathectl::cutting::LathePlant::Params p;
    p.z_origin_mm = lathectl::hal::number_param(z_origin_mm, "z_origin_mm", 0.0);
    p.cell_mm = lathectl::hal::number_param(cell_mm, "cell_mm", 0.01);
    p.max_nose_radius_mm = lathectl::io::largest_nose_radius_mm(file_tools, table_tools,
                                                                scenario_tool.nose_radius_mm);
    auto model = std::make_unique<lathectl::cutting::LathePlant>();
    model->configure(e_adaptive::lathe_process(e), p);
    const lathectl::drives::SpindlePowerAtSpeed::Drift drift{
        .factor = lathectl::hal::number_param(idle_drift, "idle_drift", 0.15),
        .warmup_s = lathectl::hal::number_param(warmup_s, "warmup_s", 120.0)};
    if (!(drift.warmup_s > 0.0) || !(drift.factor >= 0.0))
      throw lathectl::hal::Error("module parameters: warmup_s must be > 0, idle_drift >= 0");
    drive.configure(e.spindle, drift);
    // A real meter is never noiseless (a noiseless pin reads exactly the same in air at a steady
    // speed, and the sensor monitor calls it stuck): without the scenario's noise, 0.1 % of the
    // rated power.
    auto mp = e_adaptive::spindle_power_meter(e);
    if (!(mp.noise_sigma > 0.0)) mp.noise_sigma = 0.001 * e.spindle.max_power_W;
    meter.configure(mp);
    meter.reset(0.0);
    break_at = lathectl::hal::number_param(break_at_s, "break_at_s", 0.0);
    // The servo thread's period: the per-revolution window counts its samples (one revolution
    // at 1 rpm of them, allocated here).
    const auto period = static_cast<double>(
        lathectl::hal::ranged_param(period_ns, "period_ns", 1e6, 1e4, 1e8, "1e4 … 1e8"));
    force_rev.configure(period * 1e-9);
    lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    *pins->motion_type = 2;  // unconnected (halrun): every move is a feed move
    plant = std::move(model);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  plant.reset();
}
