// A downstream project using the installed lathectl package: seed 000 formula (1).
#include <cmath>
#include <cstdio>

#include "lathectl/design/pulse_regulator.hpp"

int main() {
  lathectl::design::PulseRegulatorInput in;
  in.spool_diameter_m = 0.008;
  in.slot_m = 40e-6;
  in.pressure_drop_Pa = 0.5e6;
  in.pulse_width_s = 0.01;
  in.period_s = 0.05;
  in.piston_area_m2 = 20e-4;
  const auto r = lathectl::design::pulse_regulator(in);
  std::printf("Q = %.6g m3/s\n", r.flow_m3_per_s);
  return std::abs(r.flow_m3_per_s / 4.4308e-6 - 1.0) < 1e-3 ? 0 : 1;
}
