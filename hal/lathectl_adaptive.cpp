// lathectl_adaptive — system E's machine side (seed 004: force held by the feed, cutting speed by
// V_opt = V_p·(S_p/S_cur)^y_v, and what a shop runs around it) as a realtime HAL component. The
// machine side is control::AdaptiveMachine, the object `lathectl run` and `lathectl optimize` run
// too; this file only maps HAL pins to its Input and Output and reads the files at load.
//
//   loadrt lathectl_adaptive scenario=PATH [tools=PATH] [taught=PATH] [sensor=force|power]
//                            [z_origin_mm=Z]
//   addf lathectl-adaptive servo-thread
//
// The controller's settings come from the scenario's [controller] and [sensor] sections (the
// same file `lathectl run` reads); the per-tool limits and taught references from the tools= and
// taught= files (systems/e_adaptive/tool_limits.hpp). Per-operation settings come from motion's
// analog outputs (M68 E0..E4). The period the latching detectors count is measured here
// (rtapi_get_time()), not the thread's nominal one. Pins, parameters and units:
// lathectl_adaptive(9).

#include <algorithm>
#include <cstdio>
#include <memory>

#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl_hal.hpp"
#include "pins/adaptive.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/e_adaptive/tool_limits.hpp"

MODULE_AUTHOR("lathectl");
MODULE_DESCRIPTION("lathectl system-E adaptive feed and cutting-speed controller for LinuxCNC");
MODULE_LICENSE("GPL");

LATHECTL_HAL_PARAM(
    scenario, "system-E scenario file (TOML) whose [controller] and [sensor] set the controller");
LATHECTL_HAL_PARAM(tools,
                   "per-tool limits table (TOML, optional): rating, defaults, overload levels");
LATHECTL_HAL_PARAM(taught, "teach-in references (TOML written by lathectl_oplog; absent: none)");
LATHECTL_HAL_PARAM(z_origin_mm,
                   "machine z of the stock's face: turns on the stock model for the "
                   "path-aware breakage detector (unset: the controller's own)");
LATHECTL_HAL_PARAM(sensor,
                   "force (the scenario's sensor, default) or power (spindle-power - idle)");

namespace {

constexpr const char* kName = "lathectl_adaptive";
constexpr const char* kPrefix = "lathectl-adaptive";

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_ADAPTIVE_PINS)
  LATHECTL_HAL_PARAM_BLOCK(LATHECTL_ADAPTIVE_PARAMS)
};

using lathectl::control::AdaptiveMachine;

int comp_id = -1;
Pins* pins = nullptr;
std::unique_ptr<AdaptiveMachine> machine;
AdaptiveMachine::Output out;
lathectl::hal::HomedGate homed_gate;
lathectl::hal::UpdateTimer timer;
long long last_ns = 0;

// An operation's and a teach-in's record, when a new one is out: its fields first, its
// sequence number last (lathectl_oplog reads a record once the number changes).
void write_records(Pins& p, const AdaptiveMachine::Output& o) noexcept {
  if (o.op.seq != *p.op_seq) {  // a record: its fields first, op-seq last
    *p.op_line = o.op.line;
    *p.op_tool = o.op.tool;
    *p.op_operation = o.op.operation;
    *p.op_mode = o.op.mode;
    *p.op_limit = o.op.limit;
    *p.op_load_mean = o.op.load_mean;
    *p.op_load_peak = o.op.load_peak;
    *p.op_feed_min = o.op.feed_min;
    *p.op_feed_mean = o.op.feed_mean;
    *p.op_time_in_cut = o.op.time_in_cut_s;
    *p.op_time = o.op.time_s;
    *p.op_reasons = static_cast<std::int32_t>(o.op.reasons);
    *p.op_alarm = o.op.alarm;
    *p.op_seq = o.op.seq;
  }
  if (o.teach.seq != *p.teach_seq) {
    *p.teach_tool = o.teach.tool;
    *p.teach_operation = o.teach.operation;
    *p.teach_reference = o.teach.reference;
    *p.teach_seq = o.teach.seq;
  }
}

void update(void*, long period_ns) {
  Pins& p = *pins;
  const long long now_ns = rtapi_get_time();
  AdaptiveMachine::Input in;
  in.nominal_period_s = static_cast<double>(period_ns) * 1e-9;
  in.elapsed_s = last_ns > 0 ? static_cast<double>(now_ns - last_ns) * 1e-9 : 0.0;
  last_ns = now_ns;
  p.read_pins(in, out);  // the table's copies (pins/adaptive.hpp), then what is this file's
  in.homed = homed_gate(*p.homed, *p.x_pos, *p.z_pos);
  if (*p.reset_max) timer.reset();
  timer.start();
  machine->update(in, out);
  const std::int32_t ns = timer.stop();
  if (out.control_period) *p.update_ns = ns;
  *p.update_ns_max = timer.max();
  p.write_pins(in, out);
  write_records(p, out);
}

std::string read_text(const char* path, const char* what) {
  lathectl::hal::require_readable(path, what);
  return lathectl::io::read_scenario_text(path);
}

}  // namespace

extern "C" int rtapi_app_main(void) {
  return lathectl::hal::load_component(kName, comp_id, [] {
    namespace e_adaptive = lathectl::systems::e_adaptive;
    const auto sc = lathectl::hal::load_system(scenario, e_adaptive::kReadSection);
    const auto& e = sc.get<e_adaptive::Settings>().rig;
    // What this host adds to the scenario (module parameters and files); the parameters
    // themselves are derived where every host derives them (e_adaptive::machine_params).
    e_adaptive::MachineHost host;
    const std::string sensor_kind = sensor != nullptr && *sensor != '\0' ? sensor : "force";
    if (sensor_kind != "force" && sensor_kind != "power")
      throw lathectl::hal::Error("module parameter sensor=" + sensor_kind +
                                 ": expected force or power");
    if (sensor_kind == "power") host.load = e_adaptive::MachineHost::Load::SpindlePower;
    host.z_origin_mm = z_origin_mm != nullptr && *z_origin_mm != '\0'
                           ? lathectl::hal::number_param(z_origin_mm, "z_origin_mm", 0.0)
                           : std::nan("");
    e_adaptive::ToolTable table;
    if (tools != nullptr && *tools != '\0') {
      table = e_adaptive::read_tool_table(read_text(tools, "tool limits"), tools);
      host.tools = &table;
      host.tools_file = tools;
    }
    if (taught != nullptr && *taught != '\0') {
      std::FILE* f = std::fopen(taught, "r");  // absent: nothing taught yet
      if (f != nullptr) {
        std::fclose(f);
        host.taught = e_adaptive::read_taught(read_text(taught, "taught"), taught);
        host.taught_file = taught;
      }
    }
    AdaptiveMachine::Params mp;
    try {
      mp = e_adaptive::machine_params(e, host);
    } catch (const std::invalid_argument& x) {
      throw lathectl::hal::Error(x.what());
    }
    auto m = std::make_unique<AdaptiveMachine>();
    m->configure(mp);
    Pins& p = lathectl::hal::export_pin_block(pins, comp_id, kPrefix);
    const lathectl::hal::Exporter x(comp_id, kPrefix);  // the parameters
    *p.adaptive_feed = 1.0;
    *p.operator_override = 1.0;
    *p.max_feed_override = 1.0;
    *p.feed_override = 1.0;
    *p.feed_override_counts = 1000;
    *p.feed_factor = 1.0;
    *p.spindle_override = 1.0;
    *p.program_line = -1;
    p.export_params(x, mp);
    machine = std::move(m);
    lathectl::hal::export_update(kPrefix, update, comp_id);
  });
}

extern "C" void rtapi_app_exit(void) {
  hal_exit(comp_id);
  machine.reset();
}
