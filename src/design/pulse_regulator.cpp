#include "lathectl/design/pulse_regulator.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace lathectl::design {

PulseRegulatorResult pulse_regulator(const PulseRegulatorInput& in) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string(name) + " must be > 0");
  };
  positive(in.spool_diameter_m, "spool diameter d");
  positive(in.slot_m, "slot h");
  positive(in.pressure_drop_Pa, "pressure drop Δp");
  positive(in.density_kg_per_m3, "density ρ");
  positive(in.pulse_width_s, "pulse width Δt");
  positive(in.period_s, "period T");
  positive(in.piston_area_m2, "piston area F");
  if (!(in.discharge_coefficient > 0.0 && in.discharge_coefficient <= 1.0))
    throw std::invalid_argument("discharge coefficient μ must be in (0, 1]");
  if (!(in.leak_m3_per_s_Pa >= 0.0)) throw std::invalid_argument("leakage coefficient must be ≥ 0");
  if (in.pulse_width_s > in.period_s)
    throw std::invalid_argument("pulse width Δt exceeds the period T");
  PulseRegulatorResult r;
  const double base = in.discharge_coefficient * std::numbers::pi * in.spool_diameter_m *
                      std::sqrt(2.0 * in.pressure_drop_Pa / in.density_kg_per_m3);
  r.duty = in.pulse_width_s / in.period_s;
  r.frequency_Hz = 1.0 / in.period_s;
  r.ka_m2_per_s = base * r.duty;                  // (2)
  r.kf_m3 = base * in.slot_m * in.pulse_width_s;  // (6)
  r.flow_m3_per_s = r.ka_m2_per_s * in.slot_m;    // (1)
  const double F = in.piston_area_m2;
  r.feed_no_leak_m_per_s = r.flow_m3_per_s / F;
  r.leak_m3_per_s = in.leak_m3_per_s_Pa * in.force_N / F;
  r.feed_m_per_s = r.flow_m3_per_s / F - in.leak_m3_per_s_Pa * in.force_N / (F * F);  // (3)
  r.slot_change_m = in.leak_m3_per_s_Pa * in.force_change_N / (r.ka_m2_per_s * F);    // (4)
  r.frequency_change_Hz = in.leak_m3_per_s_Pa * in.force_change_N / (r.kf_m3 * F);
  return r;
}

}  // namespace lathectl::design
