#pragma once
// Rig E: adaptive control of a CNC lathe (seed 004), wired as in its drawing:
//
//   setters 6 (force), 9/10 (s_max, s_min), 15 (S_p), 18 (V_p) ─→ controller (comparators 5, 19,
//   regulator 7, limiter 8, computer 11, divider 14, power block 16, multiplier 17)
//   ─→ feed drive 1 (servo axis, encoder = sensor 12) and spindle drive 2 (speed sensor 13)
//   ─→ cutting process 3 (stock, passes, eccentricity, hardness, random allowance, wear)
//   ─→ force-parameter sensor 4 (dynamometer Pz or Py, or cutting power from the spindle's
//      power meter minus its idle power), cutting-speed sensor 20 (V = π·D·n)
//
// The cutting process is the LinuxCNC plant's (cutting::LathePlant): the blank on a grid along z,
// cut down by the tool's path, the chip of the last revolution (feed = path travel, depth = area /
// travel), so feed changes reach the force over one revolution and entering material builds the
// chip up over the first revolution — as in a real cut, and the same integrator the simulated
// LinuxCNC machine and the optimiser's prediction run.
// The scenario's passes become a tool path: pass k feeds along +z from z_start to z_end at the
// radius D_k/2. Before it the tool retracts above the part, returns at rapid traverse and comes
// down at the approach point approach_mm before z_start; where material is left above D_k/2
// there (a shoulder: an earlier pass stopped at z_start, or the blank steps), it comes down
// approach_mm above the material at z_start and plunges radially at feed instead.
// Tool life is accounted by Palmgren–Miner: ∫ dt / T(V, s, t, h), T from the material's
// extended Taylor law with the local hardness h (Kmv = h^(−nv)); productivity as cycle time and
// material removed.

#include <cstdint>
#include <vector>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl/control/per_revolution.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/cutting/stock.hpp"
#include "lathectl/drives/feed_axis.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/sensors/faults.hpp"
#include "lathectl/sensors/force_sensor.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/e_adaptive/rig_config.hpp"

namespace lathectl::systems::e_adaptive {

class Rig {
 public:
  // Throws std::invalid_argument on an inconsistent configuration.
  void configure(const RigConfig& cfg, double dt_s, double record_interval_s,
                 double max_duration_s);
  void run() noexcept;                 // until the last pass ends or max_duration_s
  // Off: the machine's stock model cuts its own grid rather than taking the plant's cut (the
  // same numbers, at twice the grid work; a test compares). Set before configure().
  void share_cut(bool on) noexcept { share_cut_ = on; }
  [[nodiscard]] bool step() noexcept;  // false when finished

  // Streamed (no columns): attach sinks between configure() and run().
  [[nodiscard]] const sim::Recorder& recorder() const noexcept { return rec_; }
  // The load parameter's per-revolution mean and its peak over the cuts, pushed every simulation
  // step (the metrics' force_peak_rev_mean and within-5 %): from recorded rows, a 20 ms record at
  // 1700 rpm (1.7 rows a revolution) read a part 7.4 % over its limit where it was 5.6 %.
  [[nodiscard]] const control::PerRevolutionPeak& load_rev() const noexcept { return load_rev_; }
  void attach(sim::RowSink* sink) { rec_.attach(sink); }
  [[nodiscard]] const RigConfig& config() const noexcept { return cfg_; }
  // The cutting process's input and output of the last step (BM_HandLoopE replays the path).
  [[nodiscard]] const cutting::LathePlant::Input& cut_input() const noexcept { return pin_; }
  [[nodiscard]] const cutting::LathePlant::Output& cut_output() const noexcept { return pout_; }
  [[nodiscard]] bool finished() const noexcept { return pass_ >= cfg_.stock.passes.size(); }
  [[nodiscard]] double cycle_time_s() const noexcept { return t_; }
  [[nodiscard]] double time_in_cut_s() const noexcept { return t_cut_; }
  [[nodiscard]] double tool_life_used() const noexcept { return life_used_; }
  // The same integral with the hardness factor left out (T at h = 1): what the speed laws,
  // which see no hardness, are designed to hold at plan.
  [[nodiscard]] double tool_life_used_nominal_hardness() const noexcept {
    return life_used_nominal_;
  }
  [[nodiscard]] double tool_life_planned_min() const noexcept { return life_plan_min_; }
  [[nodiscard]] double material_removed_cm3() const noexcept { return removed_mm3_ / 1000.0; }
  [[nodiscard]] double programmed_feed() const noexcept {
    return machine_.controller().params().feed_programmed_mm_per_rev;
  }
  [[nodiscard]] double load_limit() const noexcept {
    return machine_.controller().params().load_limit;
  }
  [[nodiscard]] bool numerically_sound() const noexcept { return sound_; }
  // Time the controller first held the feed (feed command 0), or −1; exact, not recorded.
  // The machine side as the rig configured it (machine_params of the scenario and this host).
  [[nodiscard]] const control::AdaptiveMachine& machine() const noexcept { return machine_; }
  [[nodiscard]] double first_feed_hold_s() const noexcept { return first_hold_s_; }
  // Worst-case feed: the largest s whose worst-case force parameter stays at the limit.
  [[nodiscard]] static double worst_case_feed(const RigConfig& cfg,
                                              const cutting::CuttingModel& cut,
                                              const cutting::Stock& stock) {
    return worst_case(cfg, cut, stock).feed_mm_per_rev;
  }
  // The worst spot the scenario knows and the fixed feed it allows: the deepest pass plus 3σ of
  // the random allowance, the hardest spot, the worn tool's force factor, at V_p.
  struct WorstCase {
    double feed_mm_per_rev = 0.0;
    double depth_mm = 0.0, hardness = 1.0, wear_factor = 1.0, speed_m_per_min = 0.0;
    double parameter_at_feed = 0.0;  // the force parameter there at that feed
    bool at_min = false;             // even s_min exceeds the limit there
  };
  [[nodiscard]] static WorstCase worst_case(const RigConfig& cfg, const cutting::CuttingModel& cut,
                                            const cutting::Stock& stock);

  // The rig's program as an NC program says it: the move it is in (a feed move: a radial plunge
  // at a shoulder or the pass along +z; or a rapid: retract above the part, return along −z,
  // come down), where that move ends, and the plunge's feed bound. A run's sequence of moves is
  // the scenario's passes as a program for LinuxCNC (tests/hal/e_generated_program.cpp writes
  // it: the same path in both).
  struct Move {
    enum class Kind : std::uint8_t { Plunge, Turn, Retract, Return, Descend } kind;
    std::size_t pass = 0;
    double x_mm = 0.0;  // where the move ends: the radius (x moves) ...
    double z_mm = 0.0;  // ... or z in the stock's frame (z moves, toward +z into the part)
    double plunge_feed_max_mm_per_rev = 0.0;  // Plunge: the feed bound (LinuxCNC's M68 E2)
  };
  [[nodiscard]] Move move() const noexcept;

 private:
  // Where the tool path goes: feed moves (a radial plunge at a shoulder, the pass along +z) and
  // rapid moves between passes (retract above the part, return along −z, come down).
  enum class Phase : std::uint8_t { Plunge, Turn, Retract, Return, Descend };
  // The approach of pass k from the workpiece as it is now: where to come down and whether to
  // plunge.
  void plan_pass(std::size_t k) noexcept;
  // step()'s phases, in the order they run (rig.cpp says what each decides).
  bool advance_program(double z_mm) noexcept;
  void cut_step(double rpm, double z_mm) noexcept;
  [[nodiscard]] control::AdaptiveMachine::Input machine_input(double z_mm) const noexcept;
  void control_step(double z_mm) noexcept;
  void move_axes(double z_mm) noexcept;
  void record_step(double z_mm) noexcept;
  [[nodiscard]] bool feeding() const noexcept {
    return phase_ == Phase::Plunge || phase_ == Phase::Turn;
  }

  RigConfig cfg_{};
  bool share_cut_ = true;
  double dt_ = 5e-4;
  double t_ = 0.0;
  double max_t_ = 0.0;
  std::size_t step_ = 0;
  std::size_t record_every_ = 1;
  std::size_t control_every_ = 1;
  std::size_t pass_ = 0;
  Phase phase_ = Phase::Turn;
  double x_mm_ = 0.0;         // the tool's radius (an ideal position-controlled cross slide)
  double x_pass_mm_ = 0.0;    // this pass's radius, D_k/2
  double x_down_mm_ = 0.0;    // where the tool comes down to before the pass
  double z_approach_mm_ = 0.0;
  double x_clear_mm_ = 0.0;   // above the whole part: the return path
  double x_rate_mm_s_ = 0.0;  // the cross slide's speed in the plunge
  double plunge_feed_mm_per_rev_ = 0.0;  // the plunge's programmed feed_max
  double t_cut_ = 0.0;
  double life_used_ = 0.0;
  double life_used_nominal_ = 0.0;
  double life_plan_min_ = 0.0;
  double removed_mm3_ = 0.0;
  sensors::FaultInjector faults_;
  double force_seen_ = 0.0;
  bool sound_ = true;
  double first_hold_s_ = -1.0;
  cutting::CuttingModel cut_;  // tool life and the worst-case feed
  cutting::Stock stock_;       // the passes' geometry (the worst case; where a pass starts)
  cutting::LathePlant plant_;  // the cutting process and sensor 4's dynamometer
  cutting::LathePlant::Input pin_{};
  cutting::LathePlant::Output pout_{};
  drives::FeedAxis axis_;
  drives::SpindleDrive spindle_;
  sensors::LaggedNoisySensor power_meter_;
  control::PerRevolutionPeak load_rev_;
  control::AdaptiveMachine machine_;  // what the lathe runs: the same object as LinuxCNC's
  control::AdaptiveMachine::Output mout_{};
  double sensor_held_ = 0.0;  // sensor 4's last sample (taken every control period)
  double rpm_cmd_ = 0.0;      // the spindle's speed command
  // accumulators over a record interval
  double acc_param_ = 0.0;
  double acc_pz_ = 0.0;
  double acc_py_ = 0.0;
  double acc_depth_ = 0.0;
  double acc_power_ = 0.0;
  std::size_t acc_n_ = 0;
  sim::Recorder rec_;
};

}  // namespace lathectl::systems::e_adaptive
