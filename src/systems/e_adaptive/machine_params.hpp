#pragma once
// System E's machine side from a scenario: the one place control::AdaptiveMachine::Params are
// derived from the settings. `lathectl run` (the rig), the LinuxCNC component lathectl_adaptive
// and `lathectl optimize`'s prediction all call machine_params(); what differs between them is
// only what a host adds (MachineHost), never a policy of its own.

#include <limits>
#include <string>
#include <vector>

#include "lathectl/control/adaptive_machine.hpp"
#include "systems/e_adaptive/rig_config.hpp"
#include "systems/e_adaptive/tool_limits.hpp"

namespace lathectl::systems::e_adaptive {

// What a host adds to the scenario. The defaults are the rig's.
struct MachineHost {
  // What the load is. Sensor4: sensor 4's reading on the force input, in the scenario's unit (a
  // dynamometer's Pz or Py in N, or a cutting-power transducer's W). SpindlePower: the spindle
  // drive's electrical power, from which the machine takes the idle power (learned) and the
  // power that accelerates the spindle (the rig's power sensor, the scenario's parameter =
  // "power": seed 001's meter 13 and compensator 14; lathectl_adaptive sensor=power on any
  // scenario).
  enum class Load { Sensor4, SpindlePower };
  Load load = Load::Sensor4;
  // Machine z of the stock's face: the stock model (path-aware breakage, the feed-forward, the
  // tool-life law) runs on the scenario's blank. NaN: no stock model (the controller's own
  // collapse detector); the tool-life speed law then cannot run and is refused.
  double z_origin_mm = 0.0;
  // The feed the program is written with, when the host writes the program itself (the rig's
  // fixed mode: the worst-case feed). NaN: the scenario's controller.feed_programmed.
  double feed_programmed_mm_per_rev = std::numeric_limits<double>::quiet_NaN();
  // A machine's tool table (rating, per-tool limits) and its taught references; empty: none.
  // The files they came from name them in errors.
  const ToolTable* tools = nullptr;
  std::string tools_file{};
  std::vector<Taught> taught{};
  std::string taught_file{};
};

// Throws std::invalid_argument naming what is wrong (a host reports it at its own input: a
// module parameter, a file).
[[nodiscard]] control::AdaptiveMachine::Params machine_params(const RigConfig& e,
                                                              const MachineHost& host);

// The bar the lathe holds, as the rig's plant, LinuxCNC's simulated lathe and the machine's stock
// model all hold it: the scenario's process with its blank extended (at its end diameters, as the
// stock's law reads it) over every pass, so a one-point blank is a bar from the first pass's start
// to the last one's end. The [[fault]]s stay (a plant applies them; the machine's model drops them).
[[nodiscard]] cutting::CuttingProcess lathe_process(const RigConfig& e);

// The meter the spindle drive's power is read through: sensor 4 when it is the power meter
// (the scenario's parameter is power), else [sensor]'s power_meter_*. The rig, the simulated
// lathe lathectl_plant and the optimiser read the drive's power through it.
[[nodiscard]] sensors::LaggedNoisySensor::Params spindle_power_meter(const RigConfig& e) noexcept;

// The load's unit: "W" on the spindle's power or a power parameter, else "N".
[[nodiscard]] const char* load_unit(const RigConfig& e, const MachineHost& host) noexcept;

}  // namespace lathectl::systems::e_adaptive
