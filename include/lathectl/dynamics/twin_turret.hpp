#pragma once
// The cutting process of seed 001's twin-turret lathe: a slender part between centres cut by one
// or two tools, with regeneration — the plant that systems::b_chatter::Rig drives and that the LinuxCNC
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
//     axially by tool2_lag_mm, cuts the inner layer from the surface tool 1 left — ring 1
//     holds tool 2's own surface. Which pass of tool 1 left that surface (the inter-tool delay):
//     - AxialPositions (default, the physics): found at every step from the positions the rings
//       hold. At its material angle, tool 1's pass j revolutions (+½) back was at Z_j and cut
//       the axial band (Z_{j+1}, Z_j]; tool 2's chip spans (z2 − s2, z2], so the outer
//       boundary of its chip is the band-weighted mean of tool 1's passes over it. The delay
//       then follows the tools' actual axial offset: a modulated feed swings it by whole
//       revolutions, as the spindle-speed-variation literature's variable delay (e.g. Insperger
//       & Stépán, "Stability analysis of turning with periodic spindle speed modulation via
//       semi-discretization", J. Vib. Control 10 (2004)). Where tool 2 has overtaken tool 1's
//       last pass it meets the uncut outer layer (depth + t0 of tool 1; tool 1 does not learn
//       that this material is gone: a limit of the two-layer model, counted in uncut_reads()).
//     - Fixed: k + ½ revolutions earlier, k = round(lag/s), frozen at configure() (the model
//       before; kept to reproduce earlier results). With a constant feed it reads the pass one
//       revolution older than the one that cut z2 whenever frac(lag/s) ≥ ½.
// Process damping (optional, off by default): the flank of each tool ploughs the wavy surface it
// has just cut (Wu, ASME J. Eng. Ind. 111 (1989); Chiou & Liang, IJMTM 38 (1998); Ahmadi &
// Ismail, IJMTM 50 (2010)). With p(t) = σ_i·y(t) the tool's penetration into the part, the
// surface a distance x behind the edge is p(t − x/V); the flank there is at p(t) − c(x), with
// c = 0 on the wear land (x ≤ VB) and (x − VB)·tan γ on the clearance face beyond. The
// interference area A = ∫ max(0, p(t) − c(x) − p(t − x/V)) dx over the flank gives a radial
// force K_sp·w·A (w = b/sin κ, the engaged edge, as the force law's width). It is one-sided and
// grows steeply once the surface slope ṗ/V exceeds tan γ: an amplitude-limiting nonlinearity
// besides loss of contact. Small vibrations see on average the linear damping
// K_sp·w·VB²/(4V) (Chiou & Liang's equivalent viscous coefficient).
// Tool structure (optional): modes of each tool (the same for both turrets: each tool its own
// copy, driven by its own radial force), fixed in space — a tool's or turret's modes, or the
// modes fitted to a tap test (dynamics/frf.hpp) — in series with the part: tool i deflects away
// from the part by u_i = Σ q_ij under +F_p,i (and the ploughing force), each mode an SDOF of
// stiffness k/cos²θ along the radial line (θ its angle to it, as in a machine file) stepped
// exactly like the part's. The tool's penetration into the part is then p_i = σ_i·y − u_i: it
// replaces σ_i·y in the depth, the surface left and the ploughing.
// Only the radial plane is modelled: F_c acts in the other bending plane, whose vibration does
// not change the depth to first order.
// configure() allocates the rings and may throw; step() never allocates.

#include <cstdint>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::dynamics {

enum class TwinSetup : std::uint8_t { Single, FeedDivision, DepthDivision };
enum class InterToolDelay : std::uint8_t { AxialPositions, Fixed };

// How the force follows the instantaneous depth t, the chip dimension the radial vibration
// changes (issue 48, seed 001's quenching). Linear: Kienzle's F = k1.1·b·h^(1−m) with b = t/sin κ,
// linear in t (the default, the model of the goldens). Power: F(t) = F_linear(t0)·(t/t0)^(1−m),
// Kienzle's exponent applied to t — the classical regenerative model's view of the vibration
// normal to the cut surface as a change of chip thickness, with the power law of F. W. Taylor
// (1907, "On the art of cutting metals": 3/4, i.e. m = 0.25) that Kalmár-Nagy, Stépán & Moon
// ("Subcritical Hopf bifurcation in the delay equation model for machine tool vibrations",
// Nonlinear Dynamics 26, 2001, 121–142) expand to third order: F(t0 + Δ) = F(t0)·[1 + (1−m)·Δ/t0
// − m(1−m)/2·(Δ/t0)² + m(1−m)(1+m)/6·(Δ/t0)³ …]. m is the material's Kienzle m of each force
// (Fc for Pz, Fp for Py). The same static force at t0; the slope there is (1 − m)× the linear
// law's, and the gain of an oscillation grows with its amplitude (the cubic term): subcritical.
enum class ChipLaw : std::uint8_t { Linear, Power };

// The flank's ploughing of the surface it has just cut (see above); off unless enabled.
struct ProcessDamping {
  bool enabled = false;
  // Specific indentation force K_sp: the order reported for carbon steels (Chiou & Liang 1998
  // and Ahmadi & Ismail 2010 work with ≈ 4·10^13 N/m³); a parameter, swept in the report.
  double k_sp_N_per_m3 = 4e13;
  double wear_land_mm = 0.1;      // VB: the flank's land without clearance
  double clearance_deg = 6.0;     // γ: the clearance face beyond the land
  double flank_length_mm = 2.0;   // how far behind the edge the flank can touch
  [[nodiscard]] bool on() const noexcept { return enabled && k_sp_N_per_m3 > 0.0; }
};

class TwinTurretCut {
 public:
  static constexpr int kMaxModes = 6;
  static constexpr int kMaxToolModes = 12;
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
    // The part's displacement at the start of the cut: added to the first mode in the step a
    // tool first passes z_start (not at configure(), where it decayed before the cut by a
    // host's own time to contact and left the chatter to grow from the steps' nm asymmetry).
    double initial_disturbance_um = 1.0;
    // For sizing the rings: the spindle speed (one cell per step at it) and the feed per
    // revolution (the depth division's lag in revolutions).
    double rpm_nominal = 800.0;
    double feed_mm_per_rev = 0.1;
    InterToolDelay inter_tool_delay = InterToolDelay::AxialPositions;
    ChipLaw chip_law = ChipLaw::Linear;
    // The slowest sustained feed of tool 1 as a share of feed_mm_per_rev (a modulated feed
    // runs below it): sizes the surface memory the axial-position delay searches.
    double slowest_feed_fraction = 1.0;
    ProcessDamping process_damping{};
    // Each tool's modes (see above), at most kMaxToolModes; empty: rigid tools.
    std::vector<Mode> tool_modes{};
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
  // Tool i's deflection away from the part [m] and its penetration into it σ_i·y − u_i [m].
  [[nodiscard]] double tool_deflection_m(int i) const noexcept { return edges_[i].u; }
  [[nodiscard]] double penetration_m(int i) const noexcept {
    return edges_[i].sigma * y_ - edges_[i].u;
  }
  // Σ F_c·D/2 and Σ F_c·V at the last step.
  [[nodiscard]] double torque_N_m() const noexcept {  // in the header: a rig asks it every step
    double t = 0.0;
    for (int i = 0; i < n_tools_; ++i) t += edges_[i].fc * 0.5 * p_.part.diameter_m;
    return t;
  }
  [[nodiscard]] double power_W(double rpm) const noexcept;
  [[nodiscard]] bool sound() const noexcept { return sound_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // Depth division, axial-position delay: tool 2 steps that met material tool 1 had not cut
  // yet, and steps whose search ran past the oldest pass in memory (read there).
  [[nodiscard]] long long uncut_reads() const noexcept { return uncut_reads_; }
  [[nodiscard]] long long clipped_reads() const noexcept { return clipped_reads_; }
  // The revolutions back (+½) of tool 1's pass tool 2 read last (depth division): the delay.
  [[nodiscard]] double inter_tool_delay_rev() const noexcept { return delay_rev_; }

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
    bool axial = false;  // the surface it meets is found from the axial positions
    long long pass_hint = 0;
    double fc = 0.0, fp = 0.0, fd = 0.0, b_mm = 0.0, s_mm = 0.0;
    double u = 0.0;  // the tool's deflection away from the part
    double tq[kMaxToolModes] = {}, tqd[kMaxToolModes] = {};
    // Penetration p = σ·y over the last steps (newest at hist_at), for the ploughing.
    std::vector<double> hist;
    std::size_t hist_at = 0;
  };
  void update_modes(double x_mm) noexcept;
  // configure()'s phases, in the order they run (twin_turret.cpp says what each decides).
  static void validate(const Params& p, double dt);
  void size_surface_memory(const Params& p, double dt, int lag_revs, bool axial);
  void place_edges(const Params& p, double dt, int lag_revs, bool axial);
  void discretise_tool_modes(const Params& p);
  double read(const std::vector<double>& v, double cell) const noexcept;
  void cut(Edge& e, double theta, double rpm, double z_mm) noexcept;
  // Depth division: the outer boundary d of tool 2's chip over (z_lo, z_hi] at its cell.
  double surface_over(Edge& e, double cell, double z_lo, double z_hi) noexcept;
  // The ploughing force of the flank [N] for penetration p now, at cutting speed v [m/s].
  double ploughing(Edge& e, double p, double v_m_per_s) const noexcept;

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
  int n_tool_modes_ = 0;
  double tphi11_[kMaxToolModes] = {}, tphi12_[kMaxToolModes] = {}, tphi21_[kMaxToolModes] = {},
         tphi22_[kMaxToolModes] = {}, tg1_[kMaxToolModes] = {}, tg2_[kMaxToolModes] = {};
  double modes_at_mm_ = -1e9;
  double y_ = 0.0;
  bool seed_pending_ = false;  // initial_disturbance_um not yet applied (at the first contact)
  long long uncut_reads_ = 0, clipped_reads_ = 0;
  double delay_rev_ = 0.0;
  double sin_kappa_ = 1.0;
};

}  // namespace lathectl::dynamics
