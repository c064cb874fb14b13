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
#include "systems/c_tracer/rig_config.hpp"

namespace lathectl::systems::c_tracer {

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
