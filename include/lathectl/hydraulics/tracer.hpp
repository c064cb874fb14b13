#pragma once
// One-coordinate hydraulic copying (tracer) slide of seed 002.
//
// Geometry (our sign convention, chosen so that the seed's s_T rate reads V_pr·sin α/sin(α+β)):
// x along the part axis (the carriage feeds toward +x at V_pr = s·n/60), y the radius. The
// slide runs on guides inclined at β to the axis, its positive direction d = (−cos β, sin β):
// backward and outward. Tool and stylus ride on the slide; the stylus on the template at
//   (x_c − s·cos β, y_0 + s·sin β) + h_s·d,
// h_s its deflection along d, the spool opening h = i·h_s. With the stylus on the template, the
// zero-deflection slide position s_T(t) solves y_0 + s sin β = y_T(x_c − s cos β); on a cone of
// angle α after a cylinder, ṡ_T = V_pr·sin α / sin(α + β).
//
// Linear model, seed (8)-(9): h = P0/E0 + V_k/C0 + (M/E0)·dV_k/dt with h = i·(s_T − s), V_k = ṡ:
//   (M/E0)·s̈ + (1/C0)·ṡ + i·s = i·s_T − P0/E0
// ω_n² = i·E0/M, ζ = sqrt(E0/(M·i))/(2·C0); aperiodic for ζ ≥ 1. Steady lag on a cone, along d:
//   q_ss = (P0/E0 + V_T/C0)/i.
// Units: SI (E0 in N/m of spool opening, C0 in 1/s: slide speed per unit spool opening).

#include <complex>
#include <vector>

namespace lathectl::hydraulics {

struct TracerLinear {
  double E0_N_per_m = 2e6;   // stiffness ∂P/∂h
  double C0_per_s = 20.0;    // velocity gain ∂V/∂h
  double mass_kg = 100.0;    // M, reduced
  double lever_ratio = 3.0;  // i
  double P0_N = 500.0;       // cutting + dry friction (constant)

  [[nodiscard]] double omega_n() const noexcept;
  [[nodiscard]] double zeta() const noexcept;
  [[nodiscard]] bool aperiodic() const noexcept { return zeta() >= 1.0; }
  [[nodiscard]] double static_offset_m() const noexcept {
    return P0_N / (E0_N_per_m * lever_ratio);
  }
  [[nodiscard]] double steady_lag_m(double v_template_m_per_s) const noexcept;
  // The static characteristic of (9), dV_k/dt = 0 (the seed's Fig. 1 linearised): the spool
  // opening h = P/E0 + V_k/C0 at piston force P and copying speed V_k; Fig. 1a is P = E0·(h −
  // V_k/C0) at a held V_k, Fig. 1b V_k = C0·(h − P/E0) at a held P.
  [[nodiscard]] double static_opening_m(double P_N, double V_m_per_s) const noexcept {
    return P_N / E0_N_per_m + V_m_per_s / C0_per_s;
  }

  // Closed form of the lag q = s_T − s − P0/(E0·i) after a change at τ = 0 to a template rate
  // v [m/s], starting from q(0) = q0, q̇(0) = qd0: (M/E0)·q̈ + q̇/C0 + i·q = v/C0.
  //   cylinder → cone: q0 = 0, qd0 = v;  cone → cylinder: q0 = q_ss(v_old), qd0 = −v_old, v = 0;
  //   template step of height H along d: q0 = H, qd0 = 0, v = 0.
  [[nodiscard]] double lag(double q0, double qd0, double v, double tau) const noexcept;
  // Largest |lag| after a cylinder→cone change and the time it settles within 2 % of q_ss
  // (of its change, for a change with q_ss = 0), by scanning the closed form.
  struct Transient {
    double peak_m;
    double settling_s;
  };
  [[nodiscard]] Transient transient(double q0, double qd0, double v) const noexcept;
};

// The seed's (12)-(13): the profile error on a cone of angle α (template y = x·tan α) when the
// tool lags q along the slide d = (−cos β, sin β), i.e. sits at the template point + q·(cos β,
// −sin β). Signed tool minus template, as rig C's dx_um and dy_um:
//   (12) δx at equal y = q·cos β + q·sin β/tan α = q·sin(α + β)/sin α
//   (13) δy at equal x = −q·sin β − q·cos β·tan α = −q·sin(α + β)/cos α
// With the steady dynamic lag q = v_T/(C0·i), v_T = V_pr·sin α/sin(α + β): δx = V_pr/(C0·i),
// δy = −V_pr·tan α/(C0·i), both free of β. δx is undefined on a cylinder (α = 0), δy on a
// shoulder (α = 90°): NaN there.
struct ProfileError {
  double dx_m, dy_m;
};
[[nodiscard]] ProfileError cone_profile_error(double lag_m, double alpha_rad,
                                              double beta_rad) noexcept;

// Template profile: a polyline y_T(x) (x ascending; a vertical step is two points at one x).
class TemplateProfile {
 public:
  void add_point(double x_m, double y_m);  // throws std::invalid_argument if x goes back
  [[nodiscard]] double y_at(double x_m) const noexcept;
  // x where the template is at height y, searching from x_hint onward (for δx at equal y).
  [[nodiscard]] const std::vector<double>& xs() const noexcept { return x_; }
  [[nodiscard]] const std::vector<double>& ys() const noexcept { return y_; }
  [[nodiscard]] bool empty() const noexcept { return x_.empty(); }

 private:
  std::vector<double> x_, y_;
};

// Zero-deflection slide position s_T for carriage position x_c (bisection on a bracket).
double slide_target(const TemplateProfile& tp, double x_c, double y0, double beta_rad, double s_lo,
                    double s_hi) noexcept;

}  // namespace lathectl::hydraulics
