#pragma once
// Discrete (on/off) flow regulator 5 of seed 000: a spool of diameter d opens a slot of height h
// for a pulse of width Δt every period T = 1/f. Δp across it is held constant by the reducing
// valve, so while open q = K_o · y⁺ with K_o = μπd·sqrt(2Δp/ρ) (see orifice.hpp) and y⁺ the
// positive part of the spool's opening y.
//
// Ideal mean flow, seed (1): Q = K_o · h · Δt/T; AIM (2) Q = Ka·h, FIM (6) Q = Kf·f.
//
// Real switching: the spool moves at finite speed — it opens over `opening_time_s` and closes
// over `closing_time_s` (each for the full travel lap + max_slot) — and must first cross the
// overlap (lap) before the slot opens. Hence:
//   - a pulse shorter than lap / v_open gives no flow (dead zone),
//   - near duty 1 the spool cannot close before the next pulse and the flow saturates at the
//     continuous-opening value,
//   - between, the mean flow is bent from (1) by the opening and closing ramps.
// The slot height h is the stop (eccentric 8 in AIM): the spool cannot open past it.
//
// Integration: exact. Within a simulation step the command is piecewise constant between pulse
// edges, and the spool position is piecewise linear, so ∫ y⁺ dt is computed in closed form
// segment by segment; no sub-stepping, no edge quantisation.

#include <algorithm>
#include <cmath>

#include "lathectl/hydraulics/orifice.hpp"

namespace lathectl::hydraulics {

class PulseRegulator {
 public:
  struct Params {
    SlotOrifice orifice;
    double max_slot_m = 0.2e-3;   // travel of the spool past the lap
    double lap_m = 0.0;           // overlap to cross before the slot opens
    double opening_time_s = 0.0;  // full travel (lap + max_slot) opening time; 0 = instantaneous
    double closing_time_s = 0.0;  // full travel closing time; 0 = instantaneous
    ObliterationParams obliteration;
  };
  void configure(const Params& p);  // throws std::invalid_argument

  // Advances by dt with slot stop h [m], pulse frequency f [Hz] and pulse width Δt [s];
  // returns the mean flow over the step [m³/s]. f ≤ 0 stops pulsing (spool closes).
  double step(double dt, double slot_m, double frequency_Hz, double pulse_width_s) noexcept;

  [[nodiscard]] double opening_m() const noexcept { return y_ > 0.0 ? y_ : 0.0; }
  // Spool position past the lap edge [m]: −lap when fully closed, the slot when fully open.
  [[nodiscard]] double spool_position_m() const noexcept { return y_; }
  [[nodiscard]] const Params& params() const noexcept { return p_; }
  // Ideal mean flow by seed formula (1).
  [[nodiscard]] double ideal_flow(double slot_m, double frequency_Hz,
                                  double pulse_width_s) const noexcept;
  void reset() noexcept;

 private:
  // Moves y toward target at speed v for time tau; returns ∫ max(y, 0) dt over it and adds the
  // time with y > 0 to open_time (kLayer: with an obliteration layer, which alone needs it).
  template <bool kLayer>
  double move(double target, double v, double tau, double& open_time) noexcept;
  template <bool kLayer>
  double step_with(double dt, double slot_m, double frequency_Hz, double pulse_width_s) noexcept;

  Params p_{};
  double gain_ = 0.0;    // K_o [m³/s per m]
  double v_open_ = 0.0;  // spool speed opening [m/s]; +inf for instantaneous
  double v_close_ = 0.0;
  double phase_ = 0.0;  // position in the period, [0, 1)
  double y_ = 0.0;      // spool opening past the lap edge [m]; −lap when fully closed
  ObliterationLayer layer_;
  bool layer_on_ = false;  // an obliteration layer (layer_max_m > 0) to grow and sweep
};

// Continuous throttle (the seed's baseline): a fixed slot opening with obliteration.
class Throttle {
 public:
  struct Params {
    SlotOrifice orifice;
    ObliterationParams obliteration;
  };
  void configure(const Params& p);
  double step(double dt, double opening_m) noexcept;  // returns flow [m³/s]
  [[nodiscard]] double layer_m() const noexcept { return layer_.thickness_m(); }

 private:
  Params p_{};
  double gain_ = 0.0;
  ObliterationLayer layer_;
};

// In the header: a rig steps the regulator every step (see FeedSlide::step).
namespace detail {
// ∫ max(y, 0) over a segment where y goes linearly from y0 to y1 in time tau.
inline double positive_area(double y0, double y1, double tau) noexcept {
  if (y0 >= 0.0 && y1 >= 0.0) return 0.5 * (y0 + y1) * tau;
  if (y0 <= 0.0 && y1 <= 0.0) return 0.0;
  const double hi = std::max(y0, y1);
  const double frac = hi / (std::abs(y1 - y0));  // share of the segment above zero
  return 0.5 * hi * frac * tau;
}
// Time with y > 0 over the same segment.
inline double positive_time(double y0, double y1, double tau) noexcept {
  if (y0 > 0.0 && y1 > 0.0) return tau;
  if (y0 <= 0.0 && y1 <= 0.0) return 0.0;
  return std::max(y0, y1) / std::abs(y1 - y0) * tau;
}
}  // namespace detail

template <bool kLayer>
inline double PulseRegulator::move(double target, double v, double tau, double& open_time) noexcept {
  (void)open_time;  // kLayer alone adds to it
  const double dist = std::abs(target - y_);
  const double t_reach = std::isinf(v) ? 0.0 : dist / v;
  double area = 0.0;
  if (t_reach >= tau) {
    const double y1 = y_ + (target > y_ ? 1.0 : -1.0) * v * tau;
    area = detail::positive_area(y_, y1, tau);
    if constexpr (kLayer) open_time += detail::positive_time(y_, y1, tau);
    y_ = y1;
  } else {
    area = detail::positive_area(y_, target, t_reach) + std::max(target, 0.0) * (tau - t_reach);
    if constexpr (kLayer)
      open_time += detail::positive_time(y_, target, t_reach) + (target > 0.0 ? tau - t_reach : 0.0);
    y_ = target;
  }
  return area;
}

inline double PulseRegulator::step(double dt, double h, double f, double dt_pulse) noexcept {
  return layer_on_ ? step_with<true>(dt, h, f, dt_pulse) : step_with<false>(dt, h, f, dt_pulse);
}

template <bool kLayer>
inline double PulseRegulator::step_with(double dt, double h, double f, double dt_pulse) noexcept {
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
    [[maybe_unused]] const bool was_open = y_ > 0.0;
    area += move<kLayer>(on ? h : closed, on ? v_open_ : v_close_, seg, open_time);
    if constexpr (kLayer)
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
  if constexpr (kLayer) return gain_ * area / dt * (layer_.step(open_time, h) / h);
  return gain_ * area / dt * (h / h);  // the layer's step without a layer: h
}

}  // namespace lathectl::hydraulics
