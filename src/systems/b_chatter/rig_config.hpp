#pragma once
// System B's rig configuration: the part, the tools, the cut, the drives, the measuring chain and
// the modulation as a scenario sets them, and the cutting process's parameters derived from it.
// In the settings layer (the settings hold it; machine_params and the HAL plant use it), below the
// rig that runs it (rig.hpp).

#include <algorithm>
#include <vector>

#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/twin_turret.hpp"
#include "lathectl/sensors/vibration_chain.hpp"

namespace lathectl::systems::b_chatter {

using TwinSetup = dynamics::TwinSetup;

struct RigConfig {
  dynamics::BeamPart part;
  int modes = 2;
  // Each tool's modes, fixed in space ([structure] machine_file: the machine file's [[mode]]s and
  // the modes fitted to its [[frf]]s); empty: rigid tools, the seed's model.
  std::vector<dynamics::Mode> tool_modes;
  cutting::CuttingModel::Params cutting;  // Kienzle form
  TwinSetup setup = TwinSetup::FeedDivision;
  double depth_mm[2] = {0.5, 0.5};  // t0 per tool
  double feed_mm_per_rev = 0.25;    // programmed: S = s·n for each turret
  double rpm = 800.0;
  double overlap = 1.0;       // μ
  double tool2_lag_mm = 0.0;  // axial lag of tool 2 (depth division: the layer's trail; feed
                              // division: a set-up offset, chips s/2 + lag and s/2 − lag)
  double z_start_mm = 100.0;  // from the left centre
  double z_end_mm = 400.0;
  double approach_mm = 1.0;
  double idle_block_s = 0.5;
  double feed_drive_bandwidth_Hz = 30.0;
  // System B's lathe: a lighter spindle than SpindleDrive::Params' (the reader's defaults).
  drives::SpindleDrive::Params spindle{
      .inertia_kg_m2 = 0.2, .max_torque_N_m = 300.0, .max_power_W = 11000.0, .max_rpm = 4000.0};
  sensors::VibrationChain::Params vibration;
  sensors::PowerSensor::Params power;
  control::ModulatedFeedController::Params module;
  control::ModulationSource source = control::ModulationSource::None;  // no [modulation]: none
  control::Turret turret = control::Turret::Right;
  control::ModulationPlan programmed{};
  double initial_disturbance_um = 1.0;  // part displacement at the start of the cut
  // The modes follow the tool along the part (true), or stay at z_start (for checks against
  // the stability charts at one position).
  bool modes_follow_tool = true;
  // Depth division: the pass of tool 1 whose surface tool 2 meets, from the tools' axial
  // positions at every step (the physics) or frozen at round(lag/s) + ½ revolutions.
  dynamics::InterToolDelay inter_tool_delay = dynamics::InterToolDelay::AxialPositions;
  // The force against the depth: linear (Kienzle, the default) or the power law (t/t0)^(1−m).
  dynamics::ChipLaw chip_law = dynamics::ChipLaw::Linear;
  // The flank's ploughing (process damping); K_sp = 0: off (the default model).
  dynamics::ProcessDamping process_damping{};
  // The seed's quenching formula: the number it prints (1.41) and how the garbled text is read:
  // multiplying, A_P ≥ 1.41·a0·m_d·|ω_d² − ω_m²|, or dividing, A_P ≥ a0·m_d·|ω_d² − ω_m²|/1.41
  // (docs/system-b-chatter.md). The module's coefficient is the one or the other.
  double seed_coefficient = 1.41;
  bool seed_divides = false;
  [[nodiscard]] double module_coefficient() const noexcept {
    return seed_divides ? 1.0 / seed_coefficient : seed_coefficient;
  }
};

// The part's first modal mass with the cut at x_c_m (the module's m_d); throws as beam_modes_at.
[[nodiscard]] inline double part_modal_mass_kg(const dynamics::BeamPart& part, double x_c_m) {
  (void)dynamics::beam_modes_at(part, x_c_m, 1);  // validates
  return dynamics::beam_mode_at(part, x_c_m, 1).mass_kg;
}

// The cutting process's parameters as the scenario gives them: the one mapping the rig and the
// HAL component (hal/lathectl_chatter.cpp) both use, so a new process option reaches both.
inline dynamics::TwinTurretCut::Params cut_params(const RigConfig& cfg) {
  dynamics::TwinTurretCut::Params pp;
  pp.part = cfg.part;
  pp.modes = cfg.modes;
  pp.cutting = cfg.cutting;
  pp.setup = cfg.setup;
  pp.depth_mm[0] = cfg.depth_mm[0];
  pp.depth_mm[1] = cfg.depth_mm[1];
  pp.overlap = cfg.overlap;
  pp.tool2_lag_mm = cfg.tool2_lag_mm;
  pp.z_start_mm = cfg.z_start_mm;
  pp.modes_follow_tool = cfg.modes_follow_tool;
  pp.initial_disturbance_um = cfg.initial_disturbance_um;
  pp.rpm_nominal = cfg.rpm;
  pp.feed_mm_per_rev = cfg.feed_mm_per_rev;
  pp.inter_tool_delay = cfg.inter_tool_delay;
  pp.chip_law = cfg.chip_law;
  pp.process_damping = cfg.process_damping;
  pp.tool_modes = cfg.tool_modes;
  // The slowest feed of tool 1 (the right turret) a modulation can hold, for the surface memory.
  if (cfg.source == control::ModulationSource::Automatic)
    pp.slowest_feed_fraction = cfg.module.s_min_fraction;
  else if (cfg.source == control::ModulationSource::Programmed)
    pp.slowest_feed_fraction = std::clamp(
        cfg.programmed.s_min_mm_per_min / (cfg.feed_mm_per_rev * cfg.rpm), 0.05, 1.0);
  return pp;
}

}  // namespace lathectl::systems::b_chatter
