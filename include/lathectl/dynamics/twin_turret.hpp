#pragma once
// The cutting process of seed 001's twin-turret lathe: a slender part between centres cut by one
// or two tools, with regeneration — the plant that sim::RigB drives and that the LinuxCNC
// component drives from the machine's own axis and spindle positions.
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
// leaving the cut), the surface it met is carried forward. Per tool i:
//   depth  b_i = t0_i + σ_i·y + w·d(read)     chip  s_i = z_i − z(read)
//   Kienzle: F_c = k_c·(b/sin κ)·(s·sin κ)^(1−m_c), F_p likewise; the part feels −σ_i·F_p,i
// Set-ups:
//   single tool: ring 0, the tool reads d with the overlap factor μ (own previous revolution)
//   feed division: both tools cut one layer (ring 0) to the same radius, each taking half the
//     feed: the material a tool meets was last cut by the other turret half a revolution earlier
//     (tool2_lag_mm offsets tool 2 axially: chips s/2 + lag and s/2 − lag)
//   depth division: tool 1 cuts the outer layer (ring 0, own overlap μ); tool 2, trailing
//     axially by tool2_lag_mm, cuts the inner layer from the surface tool 1 left
//     (k + ½ revolutions earlier, k = round(lag/s)) — ring 1 holds tool 2's own surface.
// Only the radial plane is modelled: F_c acts in the other bending plane, whose vibration does
// not change the depth to first order.
// configure() allocates the rings and may throw; step() never allocates.

#include <cstdint>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/dynamics/beam.hpp"

namespace lathectl::dynamics {

enum class TwinSetup : std::uint8_t { Single, FeedDivision, DepthDivision };

class TwinTurretCut {
 public:
  static constexpr int kMaxModes = 6;
  struct Params {
    BeamPart part;
    int modes = 2;
    cutting::CuttingModel::Params cutting;  // Kienzle form is used
    TwinSetup setup = TwinSetup::FeedDivision;
    double depth_mm[2] = {0.5, 0.5};  // t0 per tool
    double overlap = 1.0;             // μ
    double tool2_lag_mm = 0.0;
    double z_start_mm = 100.0;      // the material starts here (from the left centre)
    bool modes_follow_tool = true;  // false: the modes stay at z_start (for checks)
    double initial_disturbance_um = 1.0;
    // For sizing the rings: the spindle speed (one cell per step at it) and the feed per
    // revolution (the depth division's lag in revolutions).
    double rpm_nominal = 800.0;
    double feed_mm_per_rev = 0.1;
  };
  void configure(const Params& p, double dt_s);  // throws std::invalid_argument
  // One step: the spindle's cumulative angle [rad] and speed [rpm], and the tools' axial
  // positions [mm] (tool 2 ignored for a single tool).
  void step(double theta_rad, double rpm, const double z_mm[2]) noexcept;

  [[nodiscard]] int tools() const noexcept { return n_tools_; }
  [[nodiscard]] double y_m() const noexcept { return y_; }
  [[nodiscard]] double radial_N(int i) const noexcept { return edges_[i].fp; }
  [[nodiscard]] double tangential_N(int i) const noexcept { return edges_[i].fc; }
  [[nodiscard]] double chip_mm(int i) const noexcept { return edges_[i].s_mm; }
  [[nodiscard]] double depth_mm(int i) const noexcept { return edges_[i].b_mm; }
  [[nodiscard]] bool cutting(int i) const noexcept { return edges_[i].cutting; }
  // Σ F_c·D/2 and Σ F_c·V at the last step.
  [[nodiscard]] double torque_N_m() const noexcept;
  [[nodiscard]] double power_W(double rpm) const noexcept;
  [[nodiscard]] bool sound() const noexcept { return sound_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }

 private:
  struct Ring {
    std::vector<double> d;  // radial deviation of the surface [m]
    std::vector<double> z;  // axial position of the pass [mm]
  };
  struct Edge {
    double sigma = 1.0;
    double alpha = 0.0;  // spindle angle of the tool [rad]
    std::size_t write_ring = 0;
    std::size_t d_ring = 0;
    double d_lag_rev = 1.0;  // revolutions of cells back (see cut())
    double z_lag_rev = 1.0;
    double d_weight = 1.0;
    double t0_mm = 0.0;
    long long last_cell = 0;
    bool cutting = false;
    double fc = 0.0, fp = 0.0, b_mm = 0.0, s_mm = 0.0;
  };
  void update_modes(double x_mm) noexcept;
  double read(const std::vector<double>& v, double cell) const noexcept;
  void cut(Edge& e, double theta, double rpm, double z_mm) noexcept;

  Params p_{};
  double dt_ = 2e-5;
  bool sound_ = true;
  std::size_t cells_per_rev_ = 0;
  std::size_t ring_cells_ = 0;
  std::vector<Ring> rings_;
  Edge edges_[2];
  int n_tools_ = 1;
  cutting::CuttingModel cut_;
  double q_[kMaxModes] = {}, qd_[kMaxModes] = {};
  double phi11_[kMaxModes] = {}, phi12_[kMaxModes] = {}, phi21_[kMaxModes] = {},
         phi22_[kMaxModes] = {}, g1_[kMaxModes] = {}, g2_[kMaxModes] = {}, shape_[kMaxModes] = {};
  double modes_at_mm_ = -1e9;
  double y_ = 0.0;
};

}  // namespace lathectl::dynamics
