// What `lathectl lobes` will cost (lobes.hpp, lobes_cost), estimated before anything is
// allocated: in the settings library with the machine file's reader, which refuses a file over
// its bounds before any work.
#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "systems/b_chatter/lobes_input.hpp"

namespace lathectl::systems::b_chatter {

namespace {
// The cost model of lobes_cost, its constants measured on the project's machine (AMD EPYC,
// Debian 12, -O2, CPU time of one thread; tests/dynamics timing in the commit that set them):
// - one SD cell is a root count along the unit circle at S = 4·(m + 2 + d) + 32 samples, each
//   a d×d complex determinant and the history's polynomial (d = 2·modes): 0.16 µs a sample at
//   d = 2, 0.55 at 4, 2.0 at 8, 9 at 16, i.e. ≈ 15 ns + 36 ns·d²; plus ~10 µs for the step's
//   matrix exponential and set-up;
// - one frequency-domain set evaluates Φ at kFrequencyPoints + 1 frequencies and stores each
//   lobe point (a LobePoint and its grid index; the vectors double as they grow, but the
//   capacity beyond the size is never touched, so the resident memory is about the size).
// Measured peak resident memory (/usr/bin/time): 14 MB for a small run, + 52 B per chart cell,
// + 25 B per lobe point (b_slow_high_freq.toml: 1.8e6 points, 58 MB; one 500 Hz mode over
// 20–100 000 rpm: 4.1e7 points, 1172 MB measured, 1168 MB estimated, 1.9 s user + 2.0 s sys).
constexpr double kCellSeconds = 10e-6;
constexpr double kSampleSeconds = 15e-9;
constexpr double kSampleSecondsPerD2 = 36e-9;
constexpr double kFdPointSeconds = 95e-9;      // per stored lobe point (half of it page faults)
constexpr double kFdFrequencySeconds = 60e-9;  // per frequency and mode
constexpr double kFdPointBytes = sizeof(dynamics::LobePoint) + sizeof(int);
constexpr double kChartCellBytes = sizeof(int) + 3.0 * 20.0;  // its int, its CSV row (~20 B) ×3
constexpr double kBaseBytes = 14e6;  // the program, the report, the sets' copies
constexpr double kSdBisections = 11;     // sd_limit_depth: the top, then halvings to 1e-3
constexpr double kChartBisections = 17;  // the boundary between grid depths to 1e-6

double cell_seconds(int m, int d) {
  const double samples = 4.0 * (m + 2 + d) + 32.0;
  return kCellSeconds + samples * (kSampleSeconds + kSampleSecondsPerD2 * d * d);
}

}  // namespace

LobesCost lobes_cost(const LobesInput& in, unsigned threads) {
  LobesCost c;
  c.threads = threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  const auto& sys = in.system;  // the frequency domain's (modes and a measured FRF)
  const auto& modal = in.modal;  // semi-discretization's (the FRF's fitted modes)
  const int d = 2 * static_cast<int>(modal.modes.size());
  // Frequency domain: the cutting position's set counted exactly; each position's set has the
  // same frequencies (a beam's don't move with the tool, only its stiffness does), so as many
  // points, give or take the few where Re Φ changes sign. The sets are held one at a time.
  const double points = dynamics::frequency_domain_point_count(sys, in.min_rpm, in.max_rpm,
                                                               in.max_lobes, kFrequencyPoints);
  const double sets = 1.0 + (in.part ? static_cast<double>(in.part->positions_m.size()) : 0.0);
  c.fd_points = points;
  c.fd_point_visits = points * sets;
  c.fd_seconds = sets * (points * kFdPointSeconds +
                         (kFrequencyPoints + 1.0) * static_cast<double>(sys.modes.size()) *
                             kFdFrequencySeconds);
  c.fd_bytes = points * kFdPointBytes +
               in.max_lobes * static_cast<double>(sizeof(dynamics::Lobe) + 3 * sizeof(void*));
  // The SD depths are not known before the frequency domain: its absolute limit is near the
  // softest mode's SDOF limit, which sets which modes the steps must resolve.
  double b_sdof = std::numeric_limits<double>::infinity();
  for (const auto& m : modal.modes) {
    const double c2 = std::max(std::cos(m.angle_rad) * std::cos(m.angle_rad), 1e-12);
    b_sdof = std::min(b_sdof, 2.0 * m.stiffness_N_per_m * m.damping_ratio *
                                  (1.0 + m.damping_ratio) / (modal.kf_N_per_m2 * c2));
  }
  const dynamics::SdChartOptions sd_o;
  for (int k = 0; k < in.sd_speeds; ++k) {
    const double n = in.min_rpm + (in.max_rpm - in.min_rpm) * (k + 0.5) / in.sd_speeds;
    const int m = dynamics::sd_steps_per_delay(modal, n, 3.0 * b_sdof, sd_o);
    c.max_steps = std::max(c.max_steps, m);
    c.sd_cells += kSdBisections;
    c.cell_seconds += kSdBisections * cell_seconds(m, d);
  }
  if (in.chart_speeds >= 2 && in.chart_depths >= 2) {
    dynamics::SdChartOptions o;
    o.steps_per_period = in.chart_steps_per_period;
    const double top = in.chart_max_depth_m > 0.0 ? in.chart_max_depth_m : 4.0 * b_sdof;
    const double per_speed = in.chart_depths + kChartBisections;
    for (int i = 0; i < in.chart_speeds; ++i) {
      const double n = in.min_rpm + (in.max_rpm - in.min_rpm) * i / (in.chart_speeds - 1.0);
      const int m = dynamics::sd_steps_per_delay(modal, n, top, o);
      c.max_steps = std::max(c.max_steps, m);
      c.chart_cells += per_speed;
      c.cell_seconds += per_speed * cell_seconds(m, d);
    }
    c.chart_bytes = static_cast<double>(in.chart_speeds) * in.chart_depths * kChartCellBytes;
  }
  // Each thread's SD workspace: the step's exponential (d + 6)², P and the determinant's complex
  // matrix, d² each — negligible for a few modes, gigabytes for thousands.
  c.sd_bytes = c.threads * 48.0 * (d + 6.0) * (d + 6.0);
  c.bytes = kBaseBytes + c.fd_bytes + c.chart_bytes + c.sd_bytes;
  c.seconds = c.fd_seconds + c.cell_seconds / c.threads;
  return c;
}

}  // namespace lathectl::systems::b_chatter
