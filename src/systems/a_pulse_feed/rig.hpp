#pragma once
// Rig A (systems/a_pulse_feed): the hydraulic feed slide with pulsed flow regulation (seed 000), wired as in the seed's
// figures 1 and 3:
//
//   ЗПУ (programmed feed, force set) ─┐
//   sensor Д (U_D) ─→ adder 4 / amplifier У ─→ controller ─→ AIM: eccentric drive (ЭД, Р, 8) ─→ h
//                                                        └→ FIM: converter ПЧ ─→ electromagnet ─→ f
//   pump 7 + reducing valve РК (Δp) ─→ regulator 5 (h, f, Δt) ─→ damper 6 ─→ cylinder 3 ─→ slide 2
//   slide travel, feed per revolution ─→ cutting process (Py, with disturbances) ─→ load on 3, Д
//
// The feed per revolution is the slide's travel over the last spindle revolution (chip
// thickness), taken from a ring buffer of positions. The controller runs every
// `controller_period_s`; the plant every step.

#include <cstdint>
#include <numbers>
#include <vector>

#include "lathectl/control/pulse_feed_controller.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/drives/eccentric_drive.hpp"
#include "lathectl/hydraulics/feed_slide.hpp"
#include "lathectl/hydraulics/pulse_regulator.hpp"
#include "lathectl/sensors/faults.hpp"
#include "lathectl/sensors/inductive_sensor.hpp"
#include "lathectl/sim/recorder.hpp"

#include "systems/a_pulse_feed/rig_config.hpp"

namespace lathectl::systems::a_pulse_feed {

class Rig {
 public:
  // Builds and checks the rig; throws std::invalid_argument on an inconsistent configuration or a
  // step too coarse for the hydraulics (ω_h·dt, damper and chamber time constants).
  void configure(const RigConfig& cfg, double dt_s, double record_interval_s, double duration_s);
  // One plant step of dt; records a row every record interval.
  void step() noexcept;
  void run() noexcept;  // to the configured duration

  // The machine side outside the rig (set before configure): a controller on a real machine's
  // I/O (lathectl_slide under LinuxCNC) drives this plant through actuate(); step() then runs
  // only the plant (cutting, sensor, eccentric, regulator, damper, cylinder) and records.
  void set_external(bool external) noexcept { external_ = external; }
  struct Actuation {
    bool valve_open = false;       // the spool's electromagnet is energised (this step)
    double slot_cmd_m = 0.0;       // AIM: the eccentric drive's slot command
    double frequency_Hz = 0.0;     // the pulse frequency in force (the feed's averaging window)
    control::SlideMachine::Output out;  // the controller's decision, recorded (reason, alarm)
  };
  void actuate(const Actuation& a) noexcept { act_ = a; }
  // The sensor's output as the machine reads it (faults included), after the last step.
  [[nodiscard]] double sensor_reading() const noexcept { return sensor_u_; }
  [[nodiscard]] double eccentric_slot() const noexcept { return ecc_.slot_m(); }
  [[nodiscard]] double force() const noexcept { return force_; }
  [[nodiscard]] double position() const noexcept { return slide_.state().x_m; }
  [[nodiscard]] double duration() const noexcept { return duration_; }
  [[nodiscard]] double step_size() const noexcept { return dt_; }

  [[nodiscard]] const sim::Recorder& recorder() const noexcept { return rec_; }
  // Streamed recording (set before configure): no columns, rows to the attached sinks (metrics,
  // channels.csv) — the memory of a run of any duration is bounded. Default: columns.
  // plots false: no plot pyramids either (they grow with the run), rows only to the sinks — what
  // a plant in a real-time thread records (lathectl_slide_plant).
  void set_streamed(bool streamed, bool plots = true) noexcept {
    streamed_ = streamed;
    plots_ = plots;
  }
  void attach(sim::RowSink* sink) { rec_.attach(sink); }
  // Time of the last row run() will record (the clock's own sums; −1 when it records none).
  [[nodiscard]] double last_record_time() const noexcept;
  [[nodiscard]] double record_interval() const noexcept {
    return dt_ * static_cast<double>(record_every_);
  }
  [[nodiscard]] double time() const noexcept { return t_; }
  // Time the tool reached the first disturbance (step or hardness change), or -1.
  [[nodiscard]] double first_disturbance_time() const noexcept { return t_disturbance_; }
  [[nodiscard]] double nominal_force_N() const noexcept { return force_nominal_; }
  // The tool's wear as tool life used, Σ dt / T(V, s, t, h) with T the material's extended
  // Taylor law (cutting::CuttingModel::tool_life_min, hardness through K_mv; the flank wear's
  // force growth does not shorten it): since t = 0, and from the first disturbance on with the
  // feed travel over which it was used [mm]. Fractions of one tool life.
  [[nodiscard]] double tool_life_used() const noexcept { return life_used_; }
  [[nodiscard]] double tool_life_used_after_disturbance() const noexcept { return life_used_td_; }
  [[nodiscard]] double travel_after_disturbance_mm() const noexcept {
    return t_disturbance_ < 0.0 ? 0.0 : slide_.state().x_m * 1000.0 - x_disturbance_mm_;
  }
  // Actuator setting of the uncontrolled machine: slot [m] (pulsed), opening [m] (throttle).
  [[nodiscard]] double fixed_actuator() const noexcept { return fixed_actuator_; }
  [[nodiscard]] const control::PulseFeedController& controller() const noexcept {
    return machine_.controller();
  }
  [[nodiscard]] const control::SlideMachine& machine() const noexcept { return machine_; }
  [[nodiscard]] const RigConfig& config() const noexcept { return cfg_; }
  [[nodiscard]] bool numerically_sound() const noexcept { return sound_; }
  // Oil balance of the slide since t = 0 (see hydraulics/feed_slide.hpp):
  //   delivered − leaked = swept + stored, stored = ΔW + C_d·Δp_d − ΔV_void.
  struct VolumeBalance {
    double delivered_m3 = 0.0;  // ∫q_in dt
    double leaked_m3 = 0.0;     // ∫K_leak·p_c dt
    double swept_m3 = 0.0;      // F·Δx
    double stored_m3 = 0.0;     // compressed oil + damper − void, change since t = 0
    // |delivered − leaked − swept| / delivered [%]: travel the net inflow does not explain
    // (includes the bounded storage terms).
    double travel_unexplained_pct = 0.0;
    // |delivered − leaked − swept − stored| / delivered [%]: oil made or lost by the model.
    double conservation_error_pct = 0.0;
  };
  [[nodiscard]] VolumeBalance volume_balance() const noexcept;

 private:
  double chip_feed_mm_per_rev() const noexcept;
  double position_ago(std::size_t steps) const noexcept;
  // configure()'s phases, in the order they run (rig.cpp says what each decides).
  void check_step_for_slide(const RigConfig& cfg, double dt) const;
  void set_fixed_actuator(const RigConfig& cfg, const control::SlideMachine::Params& mp);
  void start_machine(const RigConfig& cfg, const control::SlideMachine::Params& mp, double dt);
  void check_buffers(const RigConfig& cfg, double dt, double duration) const;
  void warm_up(const RigConfig& cfg, double dt);
  void prime_history(const RigConfig& cfg, double dt);
  // step()'s phases, in the order they run.
  double cut_step() noexcept;
  void control_step() noexcept;
  double regulator_flow() noexcept;
  void record_row(double x_mm) noexcept;

  RigConfig cfg_{};
  double dt_ = 1e-4;
  double t_ = 0.0;
  double duration_ = 0.0;
  bool streamed_ = false;
  bool external_ = false;
  bool plots_ = true;
  Actuation act_{};
  std::size_t step_ = 0;
  std::size_t since_control_ = 0;  // steps since the last control period (step_ % control_every_)
  std::size_t since_record_ = 0;   // steps since the last row (step_ % record_every_)
  std::size_t record_every_ = 1;
  std::size_t control_every_ = 1;
  double speed_m_per_min_ = 0.0;
  double rev_per_s_ = 0.0;
  double phi_ = 0.0;
  double force_nominal_ = 0.0;
  double fixed_actuator_ = 0.0;
  double t_disturbance_ = -1.0;
  double x_disturbance_mm_ = 0.0;
  double life_used_ = 0.0, life_used_td_ = 0.0;
  double first_change_mm_ = 0.0;
  bool sound_ = true;

  cutting::CuttingModel cut_;
  cutting::Disturbances dist_;
  hydraulics::PulseRegulator reg_;
  hydraulics::Throttle thr_;
  drives::EccentricDrive ecc_;
  hydraulics::FeedSlide slide_;
  sensors::InductiveSensor sensor_;
  control::SlideMachine machine_;  // the machine side, as lathectl_slide runs it
  control::SlideMachine::Output ctl_out_{};

  std::vector<double> x_hist_;  // ring buffer of slide positions [m]
  std::size_t hist_head_ = 0;
  std::size_t rev_steps_ = 1;
  std::size_t window_steps_ = 1;

  double force_ = 0.0;
  double depth_ = 0.0;
  double sensor_u_ = 0.0;
  sensors::FaultInjector faults_;
  double flow_acc_ = 0.0;
  double force_acc_ = 0.0;
  std::size_t acc_n_ = 0;
  double damper_volume0_ = 0.0;  // storage at t = 0, for the volume balance
  double void0_ = 0.0;
  sim::Recorder rec_;
};

}  // namespace lathectl::systems::a_pulse_feed
