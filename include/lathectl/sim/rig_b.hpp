#pragma once
// Rig B: a twin-turret lathe turning a slender part between centres (seed 001), closed-loop with
// the measurement chain and the CNC's modulated-feed module.
//
// Part: a pinned-pinned Euler–Bernoulli beam (dynamics/beam.hpp); its first n modes seen at the
// cutting position x_c (tool 1's axial position), each an SDOF stepped exactly (zero-order hold
// on the force); the modes are re-evaluated as x_c moves and the modal coordinates rescaled by
// the shape ratio, so stiffness and modal mass vary along the part. y = Σ q_j is the part's
// displacement at the tool along the line of both tools, positive toward tool 1 (right turret);
// tool 2 (left turret) stands opposite, at spindle angle π, so its radial force pushes the other
// way (σ_1 = +1, σ_2 = −1).
//
// Regeneration: the surface is kept per layer in rings indexed by cumulative material angle (K
// revolutions, N cells per revolution), holding the radial deviation d of the surface left (in
// depth terms: −σ_i·y when tool i cut it) and the axial position z of that pass. A tool reads the
// ring at its own material angle (so delays follow the spindle speed: τ = 60/n, and τ/2 for the
// other turret) and writes where it cuts; where it does not cut (depth or chip ≤ 0, the tool
// leaving the cut), the previous surface is carried forward. Per tool i:
//   depth  b_i = t0_i + σ_i·y + Σ w·d(read)     chip  s_i = z_i − z(read one revolution back)
//   Kienzle: F_c = k_c·(b/sin κ)·(s·sin κ)^(1−m_c), F_p likewise; the part feels −σ_i·F_p,i
// Set-ups:
//   single tool: ring 0, tool 1 reads d with the overlap factor μ (own previous revolution)
//   feed division: both tools cut one layer (ring 0) to the same radius, each taking half the
//     feed: the material a tool meets was last cut by the other turret half a revolution earlier
//   depth division: tool 1 cuts the outer layer (ring 0, own overlap μ); tool 2, trailing
//     axially by tool2_lag_mm, cuts the inner layer from the surface tool 1 left
//     (k + ½ revolutions earlier, k = round(lag/s)) — ring 1 holds tool 2's own surface.
// Feed drives: first-order velocity lag (bandwidth) on each turret's feed-rate command.
// Spindle: drives::SpindleDrive (speed loop, cutting torque Σ F_c·D/2, electrical power with
// speed-dependent idle losses). The NC program: an idle block (spindle at speed, no cut: the
// idle power is stored), then one cutting block from z_start to z_end.
// Measurement: VibrationChain on y; PowerSensor on the spindle's electrical power.
// Only the radial plane is modelled: F_c acts in the other bending plane, whose vibration does
// not change the depth to first order.

#include <cstdint>
#include <vector>

#include "lathectl/control/modulated_feed.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/sensors/vibration_chain.hpp"
#include "lathectl/sim/recorder.hpp"

namespace lathectl::sim {

enum class TwinSetup : std::uint8_t { Single, FeedDivision, DepthDivision };

struct RigBConfig {
  dynamics::BeamPart part;
  int modes = 2;
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
  drives::SpindleDrive::Params spindle;
  sensors::VibrationChain::Params vibration;
  sensors::PowerSensor::Params power;
  control::ModulatedFeedController::Params module;
  control::ModulationSource source = control::ModulationSource::Automatic;
  control::Turret turret = control::Turret::Right;
  control::ModulationPlan programmed{};
  double initial_disturbance_um = 1.0;  // part displacement at the start of the cut
  // The modes follow the tool along the part (true), or stay at z_start (for checks against
  // the stability charts at one position).
  bool modes_follow_tool = true;
};

class RigB {
 public:
  // dt_s: integration step; record_interval_s: recorder row interval.
  void configure(const RigBConfig& cfg, double dt_s, double record_interval_s,
                 double max_duration_s);
  void run() noexcept;
  [[nodiscard]] bool step() noexcept;  // false when the cut is finished

  [[nodiscard]] const Recorder& recorder() const noexcept { return rec_; }
  [[nodiscard]] const RigBConfig& config() const noexcept { return cfg_; }
  [[nodiscard]] double time_s() const noexcept { return t_; }
  [[nodiscard]] double cut_start_s() const noexcept { return t_cut_start_; }
  [[nodiscard]] bool numerically_sound() const noexcept { return sound_; }
  [[nodiscard]] double engaged_at_s() const noexcept { return engaged_at_; }
  [[nodiscard]] const control::ModulatedFeedController::Output& module_output() const noexcept {
    return mod_out_;
  }
  // The part's modal mass at x_c for the first mode (the m_d a user would enter).
  [[nodiscard]] static double modal_mass_kg(const dynamics::BeamPart& part, double x_c_m);
  [[nodiscard]] double programmed_feed_mm_per_min() const noexcept {
    return cfg_.feed_mm_per_rev * cfg_.rpm;
  }

 private:
  struct Ring {
    std::vector<double> d;  // radial deviation of the surface [m]
    std::vector<double> z;  // axial position of the pass [mm]
  };
  struct Tool {
    double sigma = 1.0;
    double alpha = 0.0;  // spindle angle of the tool [rad]
    double z_mm = 0.0;
    double z0_mm = 0.0;
    double v_mm_per_min = 0.0;
    double cmd_mm_per_min = 0.0;
    std::size_t write_ring = 0;
    std::size_t d_ring = 0;
    double d_lag_rev = 1.0;  // revolutions of cells back (see rig_b.cpp: cut())
    double z_lag_rev = 1.0;
    double d_weight = 1.0;
    double t0_mm = 0.0;
    long long last_cell = 0;
    bool cutting = false;
    double fc = 0.0, fp = 0.0, b_mm = 0.0, s_mm = 0.0;
  };
  void update_modes() noexcept;
  double read(const std::vector<double>& v, double cell) const noexcept;
  void cut(Tool& tool) noexcept;

  RigBConfig cfg_{};
  double dt_ = 2e-5;
  double t_ = 0.0;
  double max_t_ = 0.0;
  std::size_t step_ = 0;
  std::size_t record_every_ = 1;
  std::size_t chain_every_ = 1;
  std::size_t control_every_ = 1;
  bool sound_ = true;
  bool done_ = false;
  double t_cut_start_ = -1.0;
  double engaged_at_ = -1.0;
  double theta_ = 0.0;  // cumulative spindle angle
  std::size_t cells_per_rev_ = 0;
  std::size_t ring_cells_ = 0;
  std::vector<Ring> rings_;
  Tool tools_[2];
  int n_tools_ = 1;
  // Modes at the cutting position: state, exact one-step matrices, shape values.
  static constexpr int kMaxModes = 6;
  double q_[kMaxModes] = {}, qd_[kMaxModes] = {};
  double phi11_[kMaxModes] = {}, phi12_[kMaxModes] = {}, phi21_[kMaxModes] = {},
         phi22_[kMaxModes] = {}, g1_[kMaxModes] = {}, g2_[kMaxModes] = {}, shape_[kMaxModes] = {};
  double modes_at_mm_ = -1e9;
  double y_ = 0.0;
  double fy_ = 0.0;
  // Noise-free high-pass of y for the metrics (same cut-off as the sensor's).
  double hb0_ = 1, hb1_ = 0, hb2_ = 0, ha1_ = 0, ha2_ = 0, hx1_ = 0, hx2_ = 0, hy1_ = 0, hy2_ = 0;
  double y_hp_ = 0.0;
  cutting::CuttingModel cut_;
  drives::SpindleDrive spindle_;
  sensors::VibrationChain chain_;
  sensors::PowerSensor power_;
  control::ModulatedFeedController module_;
  control::ModulatedFeedController::Output mod_out_{};
  Recorder rec_;
};

}  // namespace lathectl::sim
