#pragma once
// A stationary Ornstein–Uhlenbeck process ξ with variance D and correlation R(τ) = D·e^{−β|τ|},
// sampled exactly on steps of h (no discretisation error whatever h):
//   ξ_0 = √D·n_0,   ξ_{k+1} = ρ·ξ_k + √(D·(1 − ρ²))·n_{k+1},   ρ = e^{−β·h},   n_k ~ N(0, 1).
// The caller draws the standard normal deviates n_k from its own generator, so a process keeps
// the random stream its host had (system D's gauging rig and its LinuxCNC plant draw from one
// seeded stream per part). Header-only: two multiplications a step.

#include <cmath>
#include <stdexcept>

namespace lathectl::dynamics {

class OrnsteinUhlenbeck {
 public:
  // variance D ≥ 0, rate β ≥ 0 [1/unit of h], step h > 0. Throws std::invalid_argument.
  void configure(double variance, double beta, double h) {
    if (!(variance >= 0.0) || !(beta >= 0.0) || !(h > 0.0) || !std::isfinite(variance) ||
        !std::isfinite(beta) || !std::isfinite(h))
      throw std::invalid_argument("Ornstein-Uhlenbeck process: need D >= 0, beta >= 0, h > 0");
    sigma_ = std::sqrt(variance);
    rho_ = std::exp(-beta * h);
    kick_ = std::sqrt(variance * (1.0 - rho_ * rho_));
    x_ = 0.0;
  }
  // A stationary start from the deviate n_0.
  double start(double n0) noexcept { return x_ = sigma_ * n0; }
  // One step h with the deviate n.
  double step(double n) noexcept { return x_ = rho_ * x_ + kick_ * n; }
  [[nodiscard]] double value() const noexcept { return x_; }
  [[nodiscard]] double sigma() const noexcept { return sigma_; }

 private:
  double sigma_ = 0.0, rho_ = 1.0, kick_ = 0.0, x_ = 0.0;
};

}  // namespace lathectl::dynamics
