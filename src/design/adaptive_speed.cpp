#include "lathectl/design/adaptive_speed.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "lathectl/cutting/feed_range.hpp"

namespace lathectl::design {

namespace {
std::string show(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}
// A quantity (speed, feed, depth, life, coefficient): finite and > 0.
void require_positive(double x, const char* name) {
  if (!(x > 0.0) || !std::isfinite(x))
    throw std::invalid_argument(std::string(name) + " must be a finite number > 0, got " + show(x));
}
// An exponent of the tool-life law: finite and ≥ 0 (0 is a handbook value, e.g. no depth term;
// the material file accepts the same range).
void require_exponent(double x, const char* name) {
  if (!(x >= 0.0) || !std::isfinite(x))
    throw std::invalid_argument(std::string(name) + " must be a finite exponent >= 0, got " +
                                show(x));
}
void require_taylor(double Cv, double m, double xv, double yv, double depth_mm,
                    double feed_mm_per_rev) {
  require_positive(Cv, "Cv");
  require_positive(m, "m");
  require_exponent(xv, "xv");
  require_exponent(yv, "yv");
  require_positive(depth_mm, "depth t [mm]");
  require_positive(feed_mm_per_rev, "feed s [mm/rev]");
}
}  // namespace

double optimal_speed(double V_p_m_per_min, double S_p_mm_per_rev, double y_v,
                     double S_cur_mm_per_rev) {
  require_positive(V_p_m_per_min, "computed speed V_p [m/min]");
  require_positive(S_p_mm_per_rev, "computed feed S_p [mm/rev]");
  require_exponent(y_v, "y_v");
  require_positive(S_cur_mm_per_rev, "current feed S [mm/rev]");
  return V_p_m_per_min * std::pow(S_p_mm_per_rev / S_cur_mm_per_rev, y_v);
}

double tool_life_min(double Cv, double m, double xv, double yv, double V_m_per_min, double depth_mm,
                     double feed_mm_per_rev) {
  require_taylor(Cv, m, xv, yv, depth_mm, feed_mm_per_rev);
  require_positive(V_m_per_min, "cutting speed V [m/min]");
  const double ratio = Cv / (V_m_per_min * std::pow(depth_mm, xv) * std::pow(feed_mm_per_rev, yv));
  return std::pow(ratio, 1.0 / m);
}

double speed_for_life(double Cv, double m, double xv, double yv, double life_min, double depth_mm,
                      double feed_mm_per_rev) {
  require_taylor(Cv, m, xv, yv, depth_mm, feed_mm_per_rev);
  require_positive(life_min, "tool life T [min]");
  return Cv / (std::pow(life_min, m) * std::pow(depth_mm, xv) * std::pow(feed_mm_per_rev, yv));
}

double feed_per_rev(double feed_rate_mm_per_min, double spindle_rpm) {
  require_positive(feed_rate_mm_per_min, "feed rate F [mm/min]");
  require_positive(spindle_rpm, "spindle speed n [rpm]");
  return feed_rate_mm_per_min / spindle_rpm;
}

PlannedMode planned_mode(const PlannedModeInput& in) {
  if (in.ranges < 1 || in.ranges > 3) throw std::invalid_argument("tool-life table: 1 to 3 ranges");
  for (int i = 0; i < in.ranges; ++i) {
    const auto& r = in.life[static_cast<std::size_t>(i)];
    require_taylor(r.Cv, r.m, r.xv, r.yv, 1.0, 1.0);
  }
  require_positive(in.kv, "speed correction Kv");
  require_positive(in.Cp, "Cp");
  require_positive(in.kp, "Kp");
  require_positive(in.depth_mm, "planned depth t_p [mm]");
  require_positive(in.life_min, "planned tool life T [min]");
  require_positive(in.feed_min_mm_per_rev, "smallest feed [mm/rev]");
  require_positive(in.nose_radius_mm, "nose radius [mm]");
  if (!(in.feed_max_mm_per_rev > in.feed_min_mm_per_rev) || !std::isfinite(in.feed_max_mm_per_rev))
    throw std::invalid_argument("largest feed must be finite and above the smallest");
  for (const double lim : {in.force_limit_N, in.power_limit_kW, in.Rz_limit_um})
    if (!(lim > 0.0)) throw std::invalid_argument("limits must be > 0");
  auto mode = [&](double s) {
    const auto* r = &cutting::feed_range(in.life, in.ranges, s);
    PlannedMode p;
    p.feed_mm_per_rev = s;
    p.speed_m_per_min = r->Cv * in.kv /
                        (std::pow(in.life_min, r->m) * std::pow(in.depth_mm, r->xv) *
                         std::pow(s, r->yv));
    p.force_N = 10.0 * in.Cp * std::pow(in.depth_mm, in.x) * std::pow(s, in.y) *
                std::pow(p.speed_m_per_min, in.n) * in.kp;
    p.power_kW = p.force_N * p.speed_m_per_min / 60.0 / 1000.0;
    p.Rz_um = s * s / (8.0 * in.nose_radius_mm) * 1000.0;
    p.mrr_cm3_per_min = in.depth_mm * s * p.speed_m_per_min;
    return p;
  };
  // The first limit a feed breaks (or FeedMax when none).
  auto broken = [&](const PlannedMode& p) {
    if (p.force_N > in.force_limit_N) return PlanLimit::Force;
    if (p.power_kW > in.power_limit_kW) return PlanLimit::Power;
    if (p.Rz_um > in.Rz_limit_um) return PlanLimit::Roughness;
    return PlanLimit::FeedMax;
  };
  PlannedMode hi = mode(in.feed_max_mm_per_rev);
  if (broken(hi) == PlanLimit::FeedMax) return hi;
  if (const PlanLimit b = broken(mode(in.feed_min_mm_per_rev)); b != PlanLimit::FeedMax)
    throw std::invalid_argument(std::string("even the smallest feed breaks the ") +
                                (b == PlanLimit::Force   ? "force"
                                 : b == PlanLimit::Power ? "power"
                                                         : "roughness") +
                                " limit");
  // Force, power and Rz all rise with the feed along V(s) (Pz ∝ s^(y − n·yv), n < 0): bisect.
  double lo = in.feed_min_mm_per_rev, up = in.feed_max_mm_per_rev;
  PlanLimit limit = broken(hi);
  for (int k = 0; k < 200 && up - lo > 1e-12 * up; ++k) {
    const double mid = 0.5 * (lo + up);
    const PlanLimit b = broken(mode(mid));
    if (b == PlanLimit::FeedMax) {
      lo = mid;
    } else {
      up = mid;
      limit = b;
    }
  }
  PlannedMode out = mode(lo);
  out.limit = limit;
  return out;
}

}  // namespace lathectl::design
