// A recorded chatter signal for lathectl_vibsensor's test (tests/hal/vibsensor_test.py): rig B
// on a scenario at its own step (the recording's sample rate, 1/run.step_s), the part's
// displacement at the tool each step converted to acceleration (its second difference), written
// as an accelerometer through an interface would give it: S32_LE samples of
// a·sensitivity/full_scale (rec.raw, for ALSA's file plugin and a WAV), and the simulated chain's
// a0 and ω_d (the rig's own VibrationChain, on the displacement) at each amplitude gate's end
// (sim.csv: time_s,a0_um,omega_d_Hz).
//
//   vibsensor_record SCENARIO OUT_DIR SENSITIVITY_V_PER_M_S2 FULL_SCALE_V
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/registry.hpp"

int main(int argc, char** argv) {
  using namespace lathectl;
  if (argc != 5) {
    std::fprintf(stderr, "usage: vibsensor_record SCENARIO OUT_DIR SENSITIVITY FULL_SCALE\n");
    return 2;
  }
  const std::string out = argv[2];
  const double counts_per_m_s2 = std::stod(argv[3]) / std::stod(argv[4]) * 2147483648.0;
  const auto sc = systems::load_scenario(argv[1], test::library());
  const auto& cfg = sc.get<systems::b_chatter::Settings>().rig;
  const double dt = sc.run.step_s;
  systems::b_chatter::Rig rig;
  rig.set_streamed(true, false);
  rig.configure(cfg, dt, sc.run.record_interval_s, sc.run.duration_s);
  const double gate = cfg.vibration.amplitude_gate_s;
  const auto per_gate = std::lround(gate / dt);
  std::vector<std::int32_t> samples;
  std::FILE* sim = std::fopen((out + "/sim.csv").c_str(), "w");
  std::fprintf(sim, "time_s,a0_um,omega_d_Hz\n");
  std::vector<double> y;  // y[n-2], y[n-1], y[n]
  long n = 0;
  for (bool more = true; more && rig.time_s() < sc.run.duration_s;) {
    more = rig.step();
    y.push_back(rig.process().y_m());
    if (y.size() == 3) {  // the acceleration at the middle sample
      const double a = (y[2] - 2.0 * y[1] + y[0]) / (dt * dt);
      samples.push_back(static_cast<std::int32_t>(std::lround(a * counts_per_m_s2)));
      y.erase(y.begin());
    } else if (y.size() == 1) {
      samples.push_back(0);  // the first sample has no second difference
    }
    if (++n % per_gate == 0) {
      const auto& chain = rig.machine().chain();
      std::fprintf(sim, "%.6f,%.9g,%.9g\n", static_cast<double>(n) * dt, chain.a0_m() * 1e6,
                   chain.omega_d() / (2.0 * std::numbers::pi));
    }
  }
  std::fclose(sim);
  std::ofstream(out + "/rec.raw", std::ios::binary)
      .write(reinterpret_cast<const char*>(samples.data()),
             static_cast<std::streamsize>(samples.size() * sizeof(std::int32_t)));
  std::printf("%zu samples at %.6g Hz\n", samples.size(), 1.0 / dt);
  return 0;
}
