#pragma once
// The one first-order lag, τ·ẏ + y = x, for every model and controller that lags a signal (a
// sensor's time constant, a motor's, a feed drive's bandwidth, a controller's filter, a learning
// rate, the obliteration layer). In core/ because sensors, drives and hydraulics use it as well as
// control (tests/layers/layer_order.cmake).
//
// Every lag of a model or controller is stepped exactly for the input it sees over the step Δt
// (forward Euler, `y += (x − y)·Δt/τ`, is unstable for Δt > 2τ and wrong by O(Δt/τ) below that;
// only a running mean's weight, with_gain(), is written that way):
//   zero-order hold   x held over the step:
//                       y ← x + (y − x)·d,  d = e^(−Δt/τ)
//   first-order hold  x linear from x0 to x1 over the step (r = τ/Δt):
//                       y ← x1 − (x1 − x0)·r + (y − x0 + (x1 − x0)·r)·d
// The zero-order hold is written two ways, the same law rounded differently; each user keeps the
// one its numbers were made with, so every golden number stays bit-identical:
//   step()            x + (y − x)·d — a plant's own lag, its input held over the simulation step:
//                     InductiveSensor, LaggedNoisySensor, EccentricDrive's motor, FeedAxis,
//                     GaugeFilter (first order; second order as two stages), VibroContactGauge's
//                     flux (τ = L·q/r changes with the gap: with_decay) and generator;
//   step_increment()  y + a·(x − y), a = 1 − d — a filter of sampled values, each held for its
//                     period: PulseFeedController's force and rate, AdaptiveFeedController's
//                     measured feed, AdaptiveMachine's power-meter terms and specific-force
//                     learning, PowerSensor's idle average, B's feed drives (from the bandwidth:
//                     with_decay), the orifice's obliteration layer (A's closed form: gain()),
//                     IdleTare's running mean (with_gain);
//   step_ramp()       first-order hold — D's filtered Ornstein–Uhlenbeck noise, a continuous
//                     process sampled at both ends of the step, taken as linear between them.
// τ ≤ 0 is no lag (d = 0, a = 1: y = x).
#include <cmath>

namespace lathectl::core {

class FirstOrderLag {
 public:
  constexpr FirstOrderLag() noexcept = default;  // no lag
  // Time constant tau_s, step dt_s.
  FirstOrderLag(double dt_s, double tau_s) noexcept
      : FirstOrderLag(with_decay(tau_s > 0.0 ? std::exp(-dt_s / tau_s) : 0.0)) {}
  // From the step's decay e^(−Δt/τ) as the caller computes it (from a bandwidth, e^(−2π·f·Δt),
  // or from a time constant that changes with the state, e^(−Δt·r/(L·q)) of a coil).
  [[nodiscard]] static constexpr FirstOrderLag with_decay(double decay) noexcept {
    FirstOrderLag lag;
    lag.decay_ = decay;
    lag.gain_ = 1.0 - decay;
    return lag;
  }
  // From the step's gain a as the caller computes it: IdleTare's running mean, a = Δt/(W + Δt)
  // while its bin holds less than τ of samples (the plain mean), then Δt/τ — the forward-Euler
  // gain, which is what an exponentially weighted mean by time is (a weight Δt/τ for the newest
  // sample), not a lag discretised from its ODE.
  [[nodiscard]] static constexpr FirstOrderLag with_gain(double gain) noexcept {
    FirstOrderLag lag;
    lag.decay_ = 1.0 - gain;
    lag.gain_ = gain;
    return lag;
  }
  [[nodiscard]] constexpr double decay() const noexcept { return decay_; }  // e^(−Δt/τ)
  [[nodiscard]] constexpr double gain() const noexcept { return gain_; }    // 1 − e^(−Δt/τ)

  // Zero-order hold, the plant's form: y after the step from y with x held over it.
  [[nodiscard]] constexpr double step(double y, double x) const noexcept {
    return x + (y - x) * decay_;
  }
  // Zero-order hold, the increment form: the same y after the step, as y + a·(x − y).
  [[nodiscard]] constexpr double step_increment(double y, double x) const noexcept {
    return y + gain_ * (x - y);
  }
  // First-order hold: x linear from x0 to x1 over the step; tau_over_dt = τ/Δt of this lag.
  [[nodiscard]] constexpr double step_ramp(double y, double x0, double x1,
                                           double tau_over_dt) const noexcept {
    return x1 - (x1 - x0) * tau_over_dt + (y - x0 + (x1 - x0) * tau_over_dt) * decay_;
  }

 private:
  double decay_ = 0.0;
  double gain_ = 1.0;
};

}  // namespace lathectl::core
