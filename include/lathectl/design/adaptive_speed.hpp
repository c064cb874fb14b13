#pragma once
// Design formulas of seed 004 and the handbook tool-life relation:
//   V_opt = V_p · (S_p / S_cur)^{y_v}                       seed 004, optimal cutting speed
//   T = (Cv / (V · t^xv · s^yv))^{1/m}                      extended Taylor (handbook) [min]
//   V_T = Cv / (T^m · t^xv · s^yv)                          speed for a target life [m/min]
//   s = F / n                                               feed per revolution [mm/rev]
//   V_p, S_p (planned_mode): the seed's criterion applied at the planned depth — the largest feed
//   the limits allow (force, cutting power, roughness Rz = s²/8r, the feed range), and the speed
//   that gives the planned tool life at that feed, V = Cv·Kv/(T^m·t^xv·s^yv), with Cv, yv of the
//   feed's range and Pz = 10·Cp·t^x·s^y·V^n·Kp (Kosilova & Meshcheryakov vol. 2, turning: the
//   feed from the limits, then the speed from the tool-life formula; the document's [3] gives
//   the result only).
// Shop units throughout (m/min, mm/rev, mm, min, mm/min, rpm), as in the handbook.

#include <array>
#include <limits>

namespace lathectl::design {

struct TaylorRange {  // one feed range of the handbook's tool-life table
  double feed_max_mm_per_rev = std::numeric_limits<double>::infinity();
  double Cv = 0.0, m = 0.2, xv = 0.15, yv = 0.35;
};

struct PlannedModeInput {
  std::array<TaylorRange, 3> life{};  // ascending feed ranges
  int ranges = 0;
  double kv = 1.0;                    // speed correction Kv (hardness Kmv, …)
  double Cp = 0.0, x = 1.0, y = 0.75, n = -0.15, kp = 1.0;  // Pz law
  double depth_mm = 0.0;              // t_p
  double life_min = 60.0;             // planned tool life T
  double feed_min_mm_per_rev = 0.05, feed_max_mm_per_rev = 0.8;
  double force_limit_N = std::numeric_limits<double>::infinity();
  double power_limit_kW = std::numeric_limits<double>::infinity();
  double Rz_limit_um = std::numeric_limits<double>::infinity();
  double nose_radius_mm = 0.8;
};

enum class PlanLimit { FeedMax, Force, Power, Roughness };

struct PlannedMode {
  double feed_mm_per_rev = 0.0;   // S_p
  double speed_m_per_min = 0.0;   // V_p
  double force_N = 0.0;           // Pz at (t_p, S_p, V_p)
  double power_kW = 0.0;          // Pz·V
  double Rz_um = 0.0;
  double mrr_cm3_per_min = 0.0;   // t·s·V
  PlanLimit limit = PlanLimit::FeedMax;  // what sets S_p
};

// Throws std::invalid_argument on bad input, or when even the smallest feed breaks a limit.
PlannedMode planned_mode(const PlannedModeInput& in);

// Throws std::invalid_argument on non-positive inputs.
double optimal_speed(double V_p_m_per_min, double S_p_mm_per_rev, double y_v,
                     double S_cur_mm_per_rev);
double tool_life_min(double Cv, double m, double xv, double yv, double V_m_per_min, double depth_mm,
                     double feed_mm_per_rev);
double speed_for_life(double Cv, double m, double xv, double yv, double life_min, double depth_mm,
                      double feed_mm_per_rev);
double feed_per_rev(double feed_rate_mm_per_min, double spindle_rpm);

}  // namespace lathectl::design
