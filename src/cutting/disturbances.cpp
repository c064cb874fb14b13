#include "lathectl/cutting/disturbances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lathectl::cutting {

namespace {
void check_ascending(const std::vector<ProfilePoint>& pts, const char* what) {
  for (std::size_t i = 1; i < pts.size(); ++i)
    if (!(pts[i].at_mm > pts[i - 1].at_mm))
      throw std::invalid_argument(std::string(what) + ": positions must be strictly ascending");
}
}  // namespace

void Disturbances::configure(const DisturbanceParams& p) {
  if (!(p.depth_mm >= 0.0)) throw std::invalid_argument("depth must be ≥ 0");
  if (!(p.step_ramp_mm >= 0.0)) throw std::invalid_argument("step ramp must be ≥ 0");
  if (!(p.random_sigma_mm >= 0.0) || !(p.random_correlation_mm > 0.0))
    throw std::invalid_argument("random allowance: σ ≥ 0 and correlation length > 0 expected");
  if (p.runout_mm < 0.0 || p.wear_VB0_mm < 0.0 || p.wear_rate_mm_per_min < 0.0 ||
      p.wear_force_gain_per_mm < 0.0)
    throw std::invalid_argument("runout and wear parameters must be ≥ 0");
  check_ascending(p.depth_steps, "depth steps");
  check_ascending(p.hardness, "hardness points");
  for (const auto& h : p.hardness)
    if (!(h.value > 0.0)) throw std::invalid_argument("hardness factor must be > 0");
  p_ = p;
  rng_.seed(p.seed);
  normal_.reset();
  random_mm_ = p.random_sigma_mm > 0.0 ? p.random_sigma_mm * normal_(rng_) : 0.0;
  last_x_ = 0.0;
}

double Disturbances::hardness_between(double x) const noexcept {
  const auto& h = p_.hardness;
  if (x <= h.front().at_mm) return h.front().value;
  if (x >= h.back().at_mm) return h.back().value;
  const auto it = std::upper_bound(h.begin(), h.end(), x,
                                   [](double v, const ProfilePoint& p) { return v < p.at_mm; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  return a.value + (b.value - a.value) * (x - a.at_mm) / (b.at_mm - a.at_mm);
}

double Disturbances::first_change_mm() const noexcept {
  double first = std::numeric_limits<double>::infinity();
  if (!p_.depth_steps.empty()) first = p_.depth_steps.front().at_mm;
  for (std::size_t i = 1; i < p_.hardness.size(); ++i)
    if (p_.hardness[i].value != p_.hardness[i - 1].value) {
      first = std::min(first, p_.hardness[i - 1].at_mm);
      break;
    }
  return first;
}

double Disturbances::random_allowance_mm(double x) noexcept {
  if (p_.random_sigma_mm > 0.0) {
    const double dx = std::abs(x - last_x_);
    if (dx > 0.0) {
      const double a = std::exp(-dx / p_.random_correlation_mm);
      random_mm_ = random_mm_ * a + p_.random_sigma_mm * std::sqrt(1.0 - a * a) * normal_(rng_);
    }
  }
  last_x_ = x;
  return random_mm_;
}

}  // namespace lathectl::cutting
