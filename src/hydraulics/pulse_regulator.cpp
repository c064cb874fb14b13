#include "lathectl/hydraulics/pulse_regulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lathectl::hydraulics {

namespace {
// ∫ max(y, 0) over a segment where y goes linearly from y0 to y1 in time tau.
double positive_area(double y0, double y1, double tau) noexcept {
  if (y0 >= 0.0 && y1 >= 0.0) return 0.5 * (y0 + y1) * tau;
  if (y0 <= 0.0 && y1 <= 0.0) return 0.0;
  const double hi = std::max(y0, y1);
  const double frac = hi / (std::abs(y1 - y0));  // share of the segment above zero
  return 0.5 * hi * frac * tau;
}
// Time with y > 0 over the same segment.
double positive_time(double y0, double y1, double tau) noexcept {
  if (y0 > 0.0 && y1 > 0.0) return tau;
  if (y0 <= 0.0 && y1 <= 0.0) return 0.0;
  return std::max(y0, y1) / std::abs(y1 - y0) * tau;
}

void check_orifice(const SlotOrifice& o) {
  if (!(o.spool_diameter_m > 0.0) || !(o.discharge_coefficient > 0.0) ||
      !(o.discharge_coefficient <= 1.0) || !(o.pressure_drop_Pa > 0.0) ||
      !(o.density_kg_per_m3 > 0.0))
    throw std::invalid_argument("orifice: d, Δp, ρ must be > 0 and 0 < μ ≤ 1");
}
}  // namespace

void PulseRegulator::configure(const Params& p) {
  check_orifice(p.orifice);
  if (!(p.max_slot_m > 0.0) || p.lap_m < 0.0 || p.opening_time_s < 0.0 || p.closing_time_s < 0.0)
    throw std::invalid_argument("pulse regulator: max slot > 0, lap and switching times ≥ 0");
  if (!(p.obliteration.removal_per_stroke >= 0.0 && p.obliteration.removal_per_stroke <= 1.0))
    throw std::invalid_argument("obliteration: removal per stroke must be in [0, 1]");
  p_ = p;
  gain_ = p.orifice.gain_per_m();
  const double travel = p.lap_m + p.max_slot_m;
  const double inf = std::numeric_limits<double>::infinity();
  v_open_ = p.opening_time_s > 0.0 ? travel / p.opening_time_s : inf;
  v_close_ = p.closing_time_s > 0.0 ? travel / p.closing_time_s : inf;
  layer_.configure(p.obliteration);
  reset();
}

void PulseRegulator::reset() noexcept {
  phase_ = 0.0;
  y_ = -p_.lap_m;
  layer_.flush();
}

double PulseRegulator::ideal_flow(double h, double f, double dt_pulse) const noexcept {
  return gain_ * h * std::clamp(dt_pulse * f, 0.0, 1.0);
}

double PulseRegulator::move(double target, double v, double tau, double& open_time) noexcept {
  const double dist = std::abs(target - y_);
  const double t_reach = std::isinf(v) ? 0.0 : dist / v;
  double area = 0.0;
  if (t_reach >= tau) {
    const double y1 = y_ + (target > y_ ? 1.0 : -1.0) * v * tau;
    area = positive_area(y_, y1, tau);
    open_time += positive_time(y_, y1, tau);
    y_ = y1;
  } else {
    area = positive_area(y_, target, t_reach) + std::max(target, 0.0) * (tau - t_reach);
    open_time += positive_time(y_, target, t_reach) + (target > 0.0 ? tau - t_reach : 0.0);
    y_ = target;
  }
  return area;
}

double PulseRegulator::step(double dt, double h, double f, double dt_pulse) noexcept {
  h = std::clamp(h, 0.0, p_.max_slot_m);
  if (y_ > h) y_ = h;  // the stop moved in
  const double closed = -p_.lap_m;
  const double duty = f > 0.0 ? std::clamp(dt_pulse * f, 0.0, 1.0) : 0.0;
  const bool pulsing = duty > 0.0 && duty < 1.0;
  double area = 0.0;
  double open_time = 0.0;  // time the slot was open in this step: the layer grows only then
  double remaining = dt;
  while (remaining > 0.0) {
    bool on = duty >= 1.0;
    double seg = remaining;
    double t_edge = 0.0;
    if (pulsing) {
      on = phase_ < duty;
      t_edge = ((on ? duty : 1.0) - phase_) / f;
      if (t_edge <= 1e-15) {  // on an edge: cross it
        phase_ = on ? duty : 0.0;
        continue;
      }
      seg = std::min(remaining, t_edge);
    }
    const bool was_open = y_ > 0.0;
    area += move(on ? h : closed, on ? v_open_ : v_close_, seg, open_time);
    if (was_open && y_ <= 0.0) layer_.sweep();  // the closing edge sweeps (a share of) it off
    if (pulsing) {
      phase_ = seg == t_edge ? (on ? duty : 0.0) : phase_ + seg * f;
    }
    remaining -= seg;
  }
  if (area <= 0.0 || h <= 0.0) return 0.0;
  // The layer grows from the oil flowing through the open slot (over the open time, so the
  // result does not depend on the step) and narrows the slot: scale the flow by effective over
  // nominal opening.
  return gain_ * area / dt * (layer_.step(open_time, h) / h);
}

void Throttle::configure(const Params& p) {
  check_orifice(p.orifice);
  p_ = p;
  gain_ = p.orifice.gain_per_m();
  layer_.configure(p.obliteration);
}

double Throttle::step(double dt, double opening_m) noexcept {
  return gain_ * layer_.step(dt, std::max(opening_m, 0.0));
}

}  // namespace lathectl::hydraulics
