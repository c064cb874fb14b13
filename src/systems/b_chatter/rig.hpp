#pragma once
// Rig B: a twin-turret lathe turning a slender part between centres (seed 001), closed-loop with
// the measurement chain and the CNC's modulated-feed module.
//
// Plant: dynamics::TwinTurretCut (the part, its modes along the cut, regeneration per layer, the
// tools leaving the cut, one tool / feed division / depth division).
// Feed drives: first-order velocity lag (bandwidth) on each turret's feed-rate command.
// Spindle: drives::SpindleDrive (speed loop, cutting torque Σ F_c·D/2, electrical power with
// speed-dependent idle losses). The NC program: an idle block (spindle at speed, no cut: the
// idle power is stored), then one cutting block from z_start to z_end.
// Measurement: VibrationChain on y; PowerSensor on the spindle's electrical power.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/core/first_order_lag.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/twin_turret.hpp"
#include "lathectl/sensors/vibration_chain.hpp"
#include "lathectl/sim/recorder.hpp"

#include "systems/b_chatter/rig_config.hpp"

namespace lathectl::systems::b_chatter {

class Rig {
 public:
  // dt_s: integration step; record_interval_s: recorder row interval.
  void configure(const RigConfig& cfg, double dt_s, double record_interval_s,
                 double max_duration_s);
  void run() noexcept;
  [[nodiscard]] bool step() noexcept;  // false when the cut is finished

  [[nodiscard]] const sim::Recorder& recorder() const noexcept { return rec_; }
  // Streamed recording (set before configure): no columns, rows to the attached sinks (the
  // study's measures, channels.csv), so memory does not grow with the cut's duration; columns
  // (the default) keep every row, at most 5e6. plots false: streamed without the plots' pyramids
  // (a run that is only measured).
  void set_streamed(bool streamed, bool plots = true) noexcept {
    streamed_ = streamed;
    plots_ = plots;
  }
  void attach(sim::RowSink* sink) { rec_.attach(sink); }
  // The most rows the configured run can record (its time bound over the record interval).
  [[nodiscard]] double max_record_rows() const noexcept { return max_rows_; }
  [[nodiscard]] const RigConfig& config() const noexcept { return cfg_; }
  [[nodiscard]] double time_s() const noexcept { return t_; }
  [[nodiscard]] double cut_start_s() const noexcept { return t_cut_start_; }
  [[nodiscard]] bool numerically_sound() const noexcept { return process_.sound(); }
  [[nodiscard]] const dynamics::TwinTurretCut& process() const noexcept { return process_; }
  [[nodiscard]] double engaged_at_s() const noexcept { return engaged_at_; }
  [[nodiscard]] const control::ModulationMachine::Output& module_output() const noexcept {
    return machine_.output();
  }
  // The machine side as configured (machine_params at this rig's periods).
  [[nodiscard]] const control::ModulationMachine& machine() const noexcept { return machine_; }
  // The coarsest step the cut can be simulated with: ω·dt ≤ 0.2 (as system C's slide) at the
  // chatter frequency f_n·√(1+2ζ) of the highest part or tool mode that can chatter in this
  // cut — one whose SDOF limit 2k(x)ζ(1+ζ) is below 4× the process stiffness Σ∂P_y/∂b of the
  // tools, with k(x) its least modal stiffness over the cut (a tool mode's: k/cos²θ). Stiffer modes are integrated exactly and cannot
  // regenerate, so they do not bind the step. f_Hz (optional) receives that chatter frequency.
  [[nodiscard]] static double max_step_s(const RigConfig& cfg, double* f_Hz = nullptr);
  // The part's modal mass at x_c for the first mode (the m_d a user would enter). Inline: the
  // section reader, which a HAL component links without the rig, derives a default from it.
  [[nodiscard]] static double modal_mass_kg(const dynamics::BeamPart& part, double x_c_m) {
    return part_modal_mass_kg(part, x_c_m);
  }

 private:
  struct Turret {  // a feed drive and its slide
    double z_mm = 0.0;
    double z0_mm = 0.0;
    double v_mm_per_min = 0.0;
    double cmd_mm_per_min = 0.0;
  };

  RigConfig cfg_{};
  double dt_ = 2e-5;
  double t_ = 0.0;
  double max_t_ = 0.0;
  std::size_t step_ = 0;
  // Steps since the last control, sensing and recorded row (step_ % control_every_ etc.).
  std::size_t since_control_ = 0, since_chain_ = 0, since_record_ = 0;
  std::size_t record_every_ = 1;
  std::size_t chain_every_ = 1;
  std::size_t control_every_ = 1;
  bool done_ = false;
  bool streamed_ = false, plots_ = true;
  double max_rows_ = 0.0;
  double t_cut_start_ = -1.0;
  double engaged_at_ = -1.0;
  double theta_ = 0.0;  // cumulative spindle angle
  Turret turrets_[2];
  core::FirstOrderLag drive_lag_;  // the feed drives' lag over one step (its exp once, here)
  int n_tools_ = 1;
  dynamics::TwinTurretCut process_;
  // Noise-free high-pass of y for the metrics (same cut-off as the sensor's).
  sensors::HighPass2 highpass_;
  double y_hp_ = 0.0;
  drives::SpindleDrive spindle_;
  control::ModulationMachine machine_;  // the CNC: chains 11–20 and the planner
  sim::Recorder rec_;
};

}  // namespace lathectl::systems::b_chatter
