#include "systems/c_tracer/rig.hpp"

#include "lathectl/sim/config_error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "lathectl/dynamics/rk4.hpp"

namespace lathectl::systems::c_tracer {

namespace {
constexpr std::size_t kChannels = 12;
std::vector<sim::Channel> rig_c_channels() {
  return {{"time_s", "s"},           {"carriage_mm", "mm"},   {"slide_mm", "mm"},
          {"slide_target_mm", "mm"}, {"lag_um", "µm"},        {"tool_x_mm", "mm"},
          {"tool_y_mm", "mm"},       {"template_y_mm", "mm"}, {"dy_um", "µm"},
          {"dx_um", "µm"},           {"load_N", "N"},         {"slide_speed_mm_per_s", "mm/s"}};
}

// Template x at height y nearest to x_hint (within ±1 mm), on segments with a slope of more than
// 10°; NaN if none: δx at equal y is reported where the template rises or falls steeply
// enough for it to mean something (on shallower features δy is the error that matters).
double template_x_at(const hydraulics::TemplateProfile& tp, double y, double x_hint) {
  const auto& xs = tp.xs();
  const auto& ys = tp.ys();
  double best = std::numeric_limits<double>::quiet_NaN(), dist = 1e300;
  for (std::size_t i = 1; i < xs.size(); ++i) {
    const double y0 = ys[i - 1], y1 = ys[i];
    // strictly inside the segment's height range (a tool on the cylinder at a shoulder's foot
    // is not on the shoulder)
    if (y <= std::min(y0, y1) + 1e-6 || y >= std::max(y0, y1) - 1e-6) continue;
    const double dx = xs[i] - xs[i - 1];
    if (dx > 0.0 && std::abs((y1 - y0) / dx) < std::tan(10.0 * std::numbers::pi / 180.0)) continue;
    const double x = xs[i - 1] + dx * (y - y0) / (y1 - y0);
    if (std::abs(x - x_hint) < dist && std::abs(x - x_hint) < 1e-3) {
      dist = std::abs(x - x_hint);
      best = x;
    }
  }
  return best;
}
}  // namespace

hydraulics::TracerLinear Rig::linearisation() const noexcept {
  if (!cfg_.nonlinear) return cfg_.linear;
  hydraulics::TracerLinear l = cfg_.linear;
  const double kq = cfg_.discharge_coefficient * cfg_.area_gradient_m *
                    std::sqrt(cfg_.supply_Pa / cfg_.density_kg_per_m3);
  l.C0_per_s = kq / cfg_.piston_area_m2;
  l.E0_N_per_m = cfg_.piston_area_m2 * kq / cfg_.clearance_leak_m3_per_s_Pa;
  return l;
}

double Rig::target(double x_c) const noexcept {
  return hydraulics::slide_target(cfg_.profile, x_c, y0_, cfg_.beta_rad, s_lo_, s_hi_);
}

double Rig::load_N(double y_tool) const noexcept {
  if (cfg_.blank_diameter_m <= 0.0) return cfg_.linear.P0_N;
  const double depth_mm = (0.5 * cfg_.blank_diameter_m - y_tool) * 1e3;
  if (depth_mm <= 0.0) return 0.0;
  const double speed = std::numbers::pi * 2.0 * y_tool * cfg_.spindle_rpm;  // m/min
  const auto f = cut_.forces({depth_mm, cfg_.feed_m_per_rev * 1e3, speed, 1.0, 1.0});
  // The cutting force resists the slide along its direction (seed 002's assumption for P0).
  return f.Px * std::cos(cfg_.beta_rad) + f.Py * std::sin(cfg_.beta_rad);
}

void Rig::configure(const RigConfig& cfg, double dt, double record_interval) {
  if (cfg.profile.xs().size() < 2) throw sim::ConfigError("template", "at least two points");
  if (!(cfg.beta_rad > 0.0 && cfg.beta_rad < std::numbers::pi / 2.0 + 1e-9))
    throw sim::ConfigError("slide.guide_angle_deg", "guide angle β must be in (0, 90°]");
  if (!(cfg.feed_m_per_rev > 0.0) || !(cfg.spindle_rpm > 0.0))
    throw sim::ConfigError("machine", "feed and speed must be > 0");
  const auto& l = cfg.linear;
  if (!(l.E0_N_per_m > 0.0 && l.C0_per_s > 0.0 && l.mass_kg > 0.0 && l.lever_ratio > 0.0) ||
      l.P0_N < 0.0)
    throw sim::ConfigError("linear", "tracer: E0, C0, M, i must be > 0 and P0 ≥ 0");
  if (!(dt > 0.0) || record_interval < dt)
    throw sim::ConfigError("run.record_interval_s", "step > 0 and record interval ≥ step");
  cfg_ = cfg;
  if (cfg.blank_diameter_m > 0.0)
    sim::configure_as("material", [&] { cut_.configure(cfg.cutting); });
  dt_ = dt;
  record_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(record_interval / dt)));
  v_pr_ = cfg.feed_m_per_rev * cfg.spindle_rpm / 60.0;
  x0_ = cfg.profile.xs().front();
  y0_ = cfg.profile.ys().front();
  t_end_ = (cfg.profile.xs().back() - x0_) / v_pr_;
  double y_min = 1e300, y_max = -1e300;
  for (double y : cfg.profile.ys()) {
    y_min = std::min(y_min, y);
    y_max = std::max(y_max, y);
  }
  const double span = (y_max - y_min) / std::sin(cfg.beta_rad) + 0.01;
  s_lo_ = -span;
  s_hi_ = span;
  const auto lin = linearisation();
  if (lin.omega_n() * dt > 0.2)
    throw sim::ConfigError("run.step_s",
                           "step too coarse for the slide's natural frequency (" +
                               std::to_string(lin.omega_n() / (2.0 * std::numbers::pi)) +
                               " Hz): use step_s ≤ " + std::to_string(0.2 / lin.omega_n()));
  t_ = 0.0;
  sound_ = true;
  if (!cfg.nonlinear) {
    q_static_ = lin.static_offset_m();
  } else {
    const double A = cfg.piston_area_m2;
    const double load = load_N(y0_) + cfg.coulomb_N;
    p_ = load / A;
    const double kq = cfg.discharge_coefficient * cfg.area_gradient_m *
                      std::sqrt(std::max(cfg.supply_Pa - p_, 0.0) / cfg.density_kg_per_m3);
    const double he = cfg.clearance_leak_m3_per_s_Pa * p_ / kq;
    // At rest after set-up the spool sits in the middle of its overlap, not at its edge: a
    // dead zone has to be crossed before the slide moves (the set-up tunes out he/i only).
    q_static_ = he / l.lever_ratio;
    const double fluid_w =
        std::sqrt(4.0 * cfg.bulk_modulus_Pa * A * A / (cfg.total_volume_m3 * l.mass_kg));
    if (fluid_w * dt > 0.2)
      throw sim::ConfigError("run.step_s",
                             "step too coarse for the hydraulic natural frequency: use step_s ≤ " +
                                 std::to_string(0.2 / fluid_w));
  }
  s_ = target(x0_) - q_static_;
  v_ = 0.0;
  max_rows_ = static_cast<std::size_t>(t_end_ / (dt * static_cast<double>(record_every_))) + 4;
  rec_ = streamed_ ? sim::Recorder::streamed(rig_c_channels())
                   : sim::Recorder(rig_c_channels(), max_rows_);
}

void Rig::run() noexcept {
  const auto& c = cfg_;
  const double cb = std::cos(c.beta_rad), sb = std::sin(c.beta_rad);
  const auto& l = c.linear;
  const std::size_t steps = static_cast<std::size_t>(t_end_ / dt_);
  for (std::size_t k = 1; k <= steps; ++k) {
    const double t0 = t_;
    double load = l.P0_N;
    if (!c.nonlinear) {
      auto acc = [&](double t, double s, double v) {
        const double st = target(x0_ + v_pr_ * t);
        return (l.E0_N_per_m / l.mass_kg) * (l.lever_ratio * (st - s) - l.P0_N / l.E0_N_per_m) -
               l.E0_N_per_m / (l.mass_kg * l.C0_per_s) * v;
      };
      dynamics::rk4_step(acc, t0, dt_, s_, v_);
    } else {
      const double x_c = x0_ + v_pr_ * t0;
      const double h_spool = l.lever_ratio * (target(x_c) - s_);
      const double he = h_spool > c.overlap_m
                            ? h_spool - c.overlap_m
                            : (h_spool < -c.overlap_m ? h_spool + c.overlap_m : 0.0);
      const double sgn = he > 0.0 ? 1.0 : (he < 0.0 ? -1.0 : 0.0);
      const double dp = std::max(c.supply_Pa - sgn * p_, 0.0);
      const double q =
          c.discharge_coefficient * c.area_gradient_m * he * std::sqrt(dp / c.density_kg_per_m3) -
          c.clearance_leak_m3_per_s_Pa * p_;
      const double y_tool = y0_ + (s_ + q_static_) * sb;
      load = load_N(y_tool);
      // Slide with Stribeck friction and stiction.
      const double drive = c.piston_area_m2 * p_ - load;
      double v = v_;
      if (v == 0.0 && std::abs(drive) <= c.static_N) {
        v = 0.0;
      } else {
        const double dir = v != 0.0 ? (v > 0.0 ? 1.0 : -1.0) : (drive > 0.0 ? 1.0 : -1.0);
        const double vs = c.stribeck_velocity_m_per_s;
        const double fr =
            (c.coulomb_N + (c.static_N - c.coulomb_N) * std::exp(-(v / vs) * (v / vs))) * dir;
        const double vn =
            (l.mass_kg * v + dt_ * (drive - fr)) / (l.mass_kg + dt_ * c.viscous_N_s_per_m);
        v = (v != 0.0 && vn * v < 0.0) ? 0.0 : vn;
      }
      v_ = v;
      s_ += v_ * dt_;
      p_ += dt_ * 4.0 * c.bulk_modulus_Pa / c.total_volume_m3 * (q - c.piston_area_m2 * v_);
    }
    t_ = t0 + dt_;
    if (!std::isfinite(s_) || !std::isfinite(v_)) {
      sound_ = false;
      return;
    }
    if (k % record_every_ != 0) continue;
    const double x_c = x0_ + v_pr_ * t_;
    const double st = target(x_c);
    const double reach = s_ + q_static_;  // setup: the tool cuts the template on the first cylinder
    const double tx = x_c - reach * cb, ty = y0_ + reach * sb;
    // δy at equal x is undefined across a vertical shoulder: masked within ±0.5 mm of one.
    // Also masked where the template is steeper than 80° (a blend running into a shoulder).
    bool near_step = false;
    for (std::size_t i = 1; i < c.profile.xs().size(); ++i) {
      const double sx = c.profile.xs()[i] - c.profile.xs()[i - 1];
      const double sy = std::abs(c.profile.ys()[i] - c.profile.ys()[i - 1]);
      const bool steep = sx <= 0.0 || sy > sx * std::tan(80.0 * std::numbers::pi / 180.0);
      if (steep && tx > c.profile.xs()[i - 1] - 0.5e-3 && tx < c.profile.xs()[i] + 0.5e-3)
        near_step = true;
    }
    const double ty_t = near_step ? std::nan("") : c.profile.y_at(tx);
    // δx at equal y where the template under the tool slopes by more than 10° (or at a shoulder).
    const double slope = (c.profile.y_at(tx + 1e-5) - c.profile.y_at(tx - 1e-5)) / 2e-5;
    const bool sloped = near_step || std::abs(slope) > std::tan(10.0 * std::numbers::pi / 180.0);
    const double tx_t = sloped ? template_x_at(c.profile, ty, tx) : std::nan("");
    const std::array<double, kChannels> row{t_,
                                            x_c * 1e3,
                                            s_ * 1e3,
                                            st * 1e3,
                                            (st - s_ - q_static_) * 1e6,
                                            tx * 1e3,
                                            ty * 1e3,
                                            c.profile.y_at(tx) * 1e3,
                                            (ty - ty_t) * 1e6,
                                            std::isnan(tx_t) ? std::nan("") : (tx - tx_t) * 1e6,
                                            c.nonlinear ? load : l.P0_N,
                                            v_ * 1e3};
    rec_.push_row(row);
  }
}

}  // namespace lathectl::systems::c_tracer
