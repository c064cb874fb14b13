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
//   feed out   (servo(), every servo period) how the staircase reaches the flagged turret
//               (Params::output): its drive's feed (rig B: Drives); one factor on every axis,
//               S(t)/F ≤ 1, the program's F being `ceiling` × the mean feed (LinuxCNC's
//               motion.adaptive-feed: Factor); or an external offset on the flagged turret's
//               axial axis moving at (S(t)/S_p − 1) × its planned velocity (Offset: the axis runs
//               at S(t)/S_p times its planned speed; motion.adaptive-feed and the feed override,
//               which scale the planned velocity, scale the modulated one alike). With the offset
//               the flag moves to the other turret only once the offset is back at 0, asked and
//               applied. The F conversion (the block's F word or path velocity to mm/min, over
//               the ceiling) is update()'s, for every output.
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
  // How the modulated feed reaches the flagged turret (the header says each).
  enum class FeedOutput { Drives, Factor, Offset };
  // The external offset's resolution [mm per count] (Offset): far below a feed step's path per
  // servo period (0.1 mm/min is 1.7 nm per ms), with ±21 m of range in an s32.
  static constexpr double kOffsetResolution_mm = 1e-5;
  // The offset's return in a feed block while not modulating, as a share of the axis's planned
  // speed: the feed stays within 10 % of the program's while it returns.
  static constexpr double kOffsetReturn = 0.1;

  struct Params {
    sensors::VibrationChain::Params vibration;  // sample_period_s: sense()'s period
    sensors::PowerSensor::Params power;
    ModulatedFeedController::Params module;  // period_s: update()'s period
    FeedOutput output = FeedOutput::Drives;
    double ceiling = 1.0;  // the program's F over the mean feed to keep (Factor; else 1)
    bool operator==(const Params&) const = default;
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
    // The block's feed as the program gives it: the path velocity [mm/s] (G94) or the F word
    // [mm/rev] (G95) at feed_rpm. Each turret present keeps that feed over Params::ceiling.
    double feed_requested = 0.0;
    bool feed_per_rev = false;
    double feed_rpm = 0.0;
    int turrets = 2;                 // turrets feeding: 2, or 1 (the right one alone)
    double path_mm[2] = {0.0, 0.0};  // path each turret has travelled (measured, or path_mm())
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
    // servo()'s: the feed out to the flagged turret.
    double mean_feed_mm_per_min = 0.0;  // the programmed feed over the ceiling (S_p)
    double factor = 1.0;        // (Factor) S(t)/F ∈ [0, 1]; 1/ceiling while not modulating
    double feed_ratio = 1.0;    // S(t)/S_p, 1 while not modulating
    double offset_mm = 0.0;     // (Offset) the external offset asked of the flagged axis
    double axis_vel_mm_per_s = 0.0;  // (Offset) the flagged axis's planned velocity
  };
  // One servo period of the host's: whether the module runs, and what the axes do.
  struct Servo {
    double dt_s = 1e-3;     // this servo period
    bool on = true;         // the module runs (enabled, its period a whole number of these)
    bool feed_block = false;  // a feed (G1, arc) block is active
    Turret turret = Turret::Right;  // the block's turret flag
    double path_velocity_mm_per_s = 0.0;  // (Factor) along the path
    double planned_mm[2] = {0.0, 0.0};    // (Offset) the axes' planned positions, right, left
    double applied_offset_mm[2] = {0.0, 0.0};  // (Offset) the offsets the axes apply
  };

  void configure(const Params& p);  // throws core::ParameterError
  // One sample of the vibration sensor: the part's displacement at the tool [m].
  void sense(double displacement_m) noexcept { chain_.update(displacement_m); }
  // One control period.
  void update(const Input& in) noexcept;
  // One servo period (a host whose turrets' travel the machine does not measure: Factor,
  // Offset), before update() in a period that runs the module: the turret the output acts on,
  // the path it has travelled, the external offset. Output: factor, feed_ratio, offset_mm,
  // axis_vel_mm_per_s (and, while off, engaged false).
  void servo(const Servo& in) noexcept;
  [[nodiscard]] Turret turret() const noexcept { return turret_; }  // the one the output acts on
  [[nodiscard]] double path_mm() const noexcept { return path_mm_; }  // servo()'s, in feed blocks
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
  // servo()'s state.
  Turret turret_ = Turret::Right;
  double ratio_ = 0.0;   // S(t)/S_p of the last module period; 0: not modulating
  double path_mm_ = 0.0;
  double planned_mm_[2] = {0.0, 0.0};
  bool planned_seen_ = false;
};

}  // namespace lathectl::control
