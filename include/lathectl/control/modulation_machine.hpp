#pragma once
// System B's machine side: what a twin-turret lathe's CNC runs between seed 001's sensors and its
// two feed drives, in one object that the simulated rig (`lathectl run`) and the LinuxCNC
// component lathectl_modfeed both run.
//
//   vibration chain (blocks 16–20)  sensors::VibrationChain: the sensor's samples of the part's
//               displacement at the tool, amplifier 17 with setter 18's dead zone, amplitude
//               detector / ADC 19 (a0) and frequency detector 20 (ω_d). Fed by sense() at the
//               sensor's own sample period (faster than the CNC's: the chatter is hundreds of Hz).
//               A machine whose detectors 19–20 are hardware in front of the CNC gives their a0
//               and ω_d in the Input instead (Input::external_detectors).
//   power chain (blocks 11–15)      sensors::PowerSensor: the main motor's active power (11),
//               switch 12 and compensator 13 storing the idle power while the NC block flagged
//               "idle" runs, adder 14 giving the cutting power N_c = N_m − N_idle.
//   planner     control::ModulatedFeedController: from a0, ω_d, m_d and N_c the staircase
//               (S_min, ΔS, Δl, n_s) for the flagged turret (automatic), or the NC block's own
//               (programmed); the other turret keeps its programmed feed.
//
// Decisions and their reasons (Output::reason): the planner's (modulation_engaged, _limited,
// _released, _programmed, _no_force) and the machine's own:
//   modulation_no_idle  vibration above the dead zone but no idle power stored yet (no idle block
//               has run, no idle table): N_m would be taken for N_c, the idle losses sized as
//               cutting force, so no plan is made until an idle block has run.
//
// Real-time: configure() may throw core::ParameterError naming its own parameter ("vibration",
// "power", or the planner's: "coefficient", "part_mass_kg", ...); sense() and update() never
// allocate, throw, lock or log.

#include "lathectl/control/modulated_feed.hpp"
#include "lathectl/control/types.hpp"
#include "lathectl/sensors/vibration_chain.hpp"

namespace lathectl::control {

class ModulationMachine {
 public:
  struct Params {
    sensors::VibrationChain::Params vibration;  // sample_period_s: sense()'s period
    sensors::PowerSensor::Params power;
    ModulatedFeedController::Params module;  // period_s: update()'s period
  };
  struct Input {
    // Detectors 19–20 outside the CNC: their readings replace the machine's own chain.
    bool external_detectors = false;
    double a0_m = 0.0;               // (external) 0 below the dead zone
    double omega_d_rad_per_s = 0.0;  // (external) 0 below the dead zone
    double motor_power_W = 0.0;      // the main motor's active power (sensor 11's input)
    bool idle_block = false;         // the NC block is flagged idle (switch 12)
    double rpm = 0.0;                // spindle speed
    double speed_m_per_min = 0.0;    // cutting speed V
    double feed_programmed_mm_per_min[2] = {0.0, 0.0};  // S1 (right), S2 (left)
    double path_mm[2] = {0.0, 0.0};  // path each turret has travelled (measured)
    bool feed_block = false;         // a cutting block is active
    ModulationSource source = ModulationSource::Automatic;
    Turret turret = Turret::Right;  // the block's turret flag
    ModulationPlan programmed{};    // the block's parameters (source Programmed)
  };
  // The planner's output (feeds to drives 3 and 6, the plan, why) and what the chains read.
  struct Output : ModulatedFeedController::Output {
    double a0_m = 0.0;               // the a0 the planner saw
    double omega_d_rad_per_s = 0.0;  // the ω_d the planner saw
    double cut_power_W = 0.0;        // N_c (adder 14)
    double idle_power_W = 0.0;       // N_idle (compensator 13)
    bool idle_known = false;         // an idle power is stored (or tabulated)
  };

  void configure(const Params& p);  // throws core::ParameterError
  // One sample of the vibration sensor: the part's displacement at the tool [m].
  void sense(double displacement_m) noexcept { chain_.update(displacement_m); }
  // One control period.
  void update(const Input& in) noexcept;
  [[nodiscard]] const Output& output() const noexcept { return out_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  [[nodiscard]] const sensors::VibrationChain& chain() const noexcept { return chain_; }
  [[nodiscard]] const sensors::PowerSensor& power() const noexcept { return power_; }
  // The planner, for a ModulationPlanner's run() in a slower thread, and its counts.
  [[nodiscard]] const ModulatedFeedController& controller() const noexcept { return module_; }
  void use_planner(ModulationPlanner* planner) noexcept { module_.use_planner(planner); }

 private:
  Params p_{};
  bool configured_ = false;
  sensors::VibrationChain chain_;
  sensors::PowerSensor power_;
  ModulatedFeedController module_;
  bool idle_known_ = false;
  Output out_{};
};

}  // namespace lathectl::control
