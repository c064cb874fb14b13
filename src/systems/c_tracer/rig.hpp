#pragma once
// Rig C (systems/c_tracer): a template copied onto the part by the one-coordinate hydraulic tracer slide (seed 002).
//
//   carriage x_c = x_start + V_pr·t ─→ template under the stylus ─→ deflection h_s = s_T − s
//   ─→ spool h = i·h_s ─→ linear model (seed (8)-(9)), or the nonlinear servo:
//        4-way spool, supply p_s, overlap u, effective opening h_e = sgn(h)·max(|h| − u, 0),
//        Q = C_d·w·h_e·sqrt((p_s − sgn(h_e)·p_L)/ρ) − K_c·p_L   (K_c: clearance leakage)
//        (V_t/4B)·ṗ_L = Q − A·v,    M·v̇ = A·p_L − F_cut(t) − F_fr(v)
//        F_fr: Stribeck, (F_c + (F_s − F_c)·e^{−(v/v_s)²})·sgn v + b·v, with stiction
//        F_cut: the cutting force along the slide (handbook model; depth from the blank radius)
//   ─→ slide s ─→ tool at the template point minus h_s·d: the part profile.
// Its linearisation: C0 = C_d·w·sqrt(p_s/ρ)/A, E0 = A·C_d·w·sqrt(p_s/ρ)/K_c.
// Integration: RK4 for the linear model (validated against the closed form); the nonlinear model
// by semi-implicit Euler with the friction's stiction handled as in FeedSlide.

#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/hydraulics/tracer.hpp"
#include "lathectl/sim/recorder.hpp"

namespace lathectl::systems::c_tracer {

struct TracerFeature {
  std::string kind;        // "line", "cone", "step", "arc"
  double x_start_m = 0.0;  // where it starts on the template
  double x_end_m = 0.0;
};

struct RigConfig {
  hydraulics::TemplateProfile profile;
  std::vector<TracerFeature> features;
  double beta_rad = 1.0;           // guide inclination β
  double feed_m_per_rev = 0.2e-3;  // s
  double spindle_rpm = 500.0;      // n
  bool nonlinear = false;
  hydraulics::TracerLinear linear;  // used when !nonlinear (and reported as the linearisation)
  // nonlinear servo
  double supply_Pa = 4e6;
  double discharge_coefficient = 0.65;
  double area_gradient_m = 0.01;  // w: spool port width
  double density_kg_per_m3 = 870.0;
  double overlap_m = 0.0;
  double clearance_leak_m3_per_s_Pa = 1e-12;  // K_c
  double piston_area_m2 = 20e-4;
  double total_volume_m3 = 200e-6;
  double bulk_modulus_Pa = 1.4e9;
  // Friction: none unless [friction] gives it (the scenario reader's defaults; before one default
  // per key, a scenario without the table got 200 N, 200 N and 2000 N·s/m, one with an empty table
  // zeros).
  double coulomb_N = 0.0;
  double static_N = 0.0;  // ≥ coulomb_N; the reader's default is coulomb_N
  double stribeck_velocity_m_per_s = 1e-4;
  double viscous_N_s_per_m = 0.0;
  // cutting (nonlinear model); blank diameter ≤ 0 → constant load P0 = linear.P0_N instead
  cutting::CuttingModel::Params cutting;
  double blank_diameter_m = 0.0;
};

class Rig {
 public:
  void configure(const RigConfig& cfg, double dt_s, double record_interval_s);  // throws
  void run() noexcept;  // across the template
  [[nodiscard]] const sim::Recorder& recorder() const noexcept { return rec_; }
  // Streamed recording (set before configure): no columns, rows to the sinks attached between
  // configure() and run() (metrics, channels.csv), so memory does not grow with the run's length.
  void set_streamed(bool streamed) noexcept { streamed_ = streamed; }
  void attach(sim::RowSink* sink) { rec_.attach(sink); }
  // The most rows run() records (the columns' capacity; channels.csv's disk-space check).
  [[nodiscard]] std::size_t max_rows() const noexcept { return max_rows_; }
  [[nodiscard]] const RigConfig& config() const noexcept { return cfg_; }
  [[nodiscard]] double carriage_speed() const noexcept { return v_pr_; }
  // The nonlinear servo's linearisation at the centre (C0, E0), for comparison.
  [[nodiscard]] hydraulics::TracerLinear linearisation() const noexcept;
  [[nodiscard]] double static_offset_m() const noexcept { return q_static_; }
  [[nodiscard]] bool numerically_sound() const noexcept { return sound_; }

 private:
  double target(double x_c) const noexcept;
  double load_N(double y_tool_m) const noexcept;  // cutting force along the slide
  RigConfig cfg_{};
  double dt_ = 1e-4, t_ = 0.0, t_end_ = 0.0, v_pr_ = 0.0, y0_ = 0.0, x0_ = 0.0;
  double s_ = 0.0, v_ = 0.0, p_ = 0.0, q_static_ = 0.0;
  double s_lo_ = -1.0, s_hi_ = 1.0;
  std::size_t record_every_ = 1, max_rows_ = 0;
  bool sound_ = true, streamed_ = false;
  cutting::CuttingModel cut_;
  sim::Recorder rec_;
};

}  // namespace lathectl::systems::c_tracer
