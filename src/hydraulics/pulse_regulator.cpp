#include "lathectl/hydraulics/pulse_regulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lathectl::hydraulics {

namespace {
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
  layer_on_ = p.obliteration.layer_max_m > 0.0;
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
