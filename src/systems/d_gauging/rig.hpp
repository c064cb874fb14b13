#pragma once
// In-process gauging (system D): the part's controlled size x(t) = m_x − a·t, the disturbance
// ξ(t) (Ornstein–Uhlenbeck: variance D, R(τ) = D·e^{−β|τ|}) that the gauge sees on top of it,
// the gauge (full electromechanical or linearised), the relay with its threshold and response
// time, and the machine that stops removing material on the relay's command.
//
// Linearised part, exactly at any step: S = S_det + ε, S_det(t) = K·(A − m_x + a·(t − T_f)) (the
// filter's ramp response after its lag, (21)), and (ξ, ε) the 2-D Gauss–Markov system
//   dξ = −β·ξ·dt + sqrt(2βD)·dW,   T_f·ε' + ε = −K·ξ
// advanced by its exact transition Φ(h) with noise covariance Q = P − Φ·P·Φᵀ, P its stationary
// covariance (Var ε = D·K²/(1 + βT_f), seed (25); Cov(ξ, ε) = −K·D/(1 + βT_f)). A part is
// simulated from a few correlation times before its expected trip, starting from the
// stationary distribution (exact, since the noise is stationary and the lag long settled).
// The relay trips at the first upward crossing of S_th (interpolated between steps); removal
// stops t_r later, or at the backstop if x reaches it first. The finished size is the true size
// then: ξ disturbs the measurement, not the part.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/d_gauging/settings.hpp"

#include "systems/d_gauging/rig_config.hpp"

namespace lathectl::systems::d_gauging {

struct LinearGauge {
  using Filter = sensors::VibroContactGauge::Params::Filter;
  double gain_V_per_m = 0.0;  // K
  double intercept_m = 0.0;   // B0/q1 (A0 in the seed's approximation)
  double filter_s = 0.1;      // T_f
  Filter filter = Filter::FirstOrder;
  double supply_Hz = 50.0;  // sets the synchronous filter's window
  [[nodiscard]] sensors::VibroContactGauge::Params filter_params() const {
    sensors::VibroContactGauge::Params q;
    q.filter_time_constant_s = filter_s;
    q.filter = filter;
    q.supply_Hz = supply_Hz;
    return q;
  }
  // The ramp lag: T_f (first and second order) or T_w/2 (synchronous).
  [[nodiscard]] double lag_s() const {
    return sensors::VibroContactGauge::filter_lag_s(filter_params());
  }
  // (25) extended: Var ε / (D·K²).
  [[nodiscard]] double noise_factor(double beta) const {
    return sensors::VibroContactGauge::filter_noise_factor(filter_params(), beta);
  }
};
// The line (K, B) with the transducer's filter.
LinearGauge linear_gauge(const design::GaugeLine& line,
                         const sensors::VibroContactGauge::Params& t);

// Threshold (23), the filter's ramp lag for T_f.
double threshold_23(const LinearGauge& g, const GaugingProcess& p);

struct PartResult {
  double trip_s = 0.0;      // relay trips (NaN if never within the run)
  double stop_s = 0.0;      // removal stops
  double finished_m = 0.0;  // true x when removal stopped
  bool backstop = false;    // the cut ended at the backstop (relay too late or never)
  // Full model with a cycle: the true size x when each earlier step's command operated (the
  // removal rate changed), in order; NaN for a step that did not.
  std::array<double, control::GaugeMachine::kMaxSteps> step_at_m{
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  // Linearised Monte Carlo: the filtered noise ε at the nominal trip time t* (S_det(t*) = S_th),
  // NaN if not reached: highly correlated with the finished size, known mean 0 — the control
  // variate that makes the bias calibration precise.
  double noise_at_nominal_V = std::numeric_limits<double>::quiet_NaN();
};

// Linearised Monte Carlo: N parts, each with its own stream (seed, part index), on `threads`
// threads (0 = all cores). Results in part order: reproducible whatever the thread count.
std::vector<PartResult> monte_carlo_linear(const GaugingProcess& p, const LinearGauge& g,
                                           double threshold_V, std::size_t parts,
                                           std::uint64_t seed, unsigned threads = 0);
// Parts are machined in chunks of this many (a chunk's parts share a noise filter's buffer).
constexpr std::size_t kLinearPartChunk = 1024;
// The parts first … first + out.size() − 1 of that Monte Carlo into `out`: the same results as
// the whole run's when `first` is a multiple of kLinearPartChunk.
void monte_carlo_linear(const GaugingProcess& p, const LinearGauge& g, double threshold_V,
                        std::size_t first, std::span<PartResult> out, std::uint64_t seed,
                        unsigned threads = 0);

// The parts of monte_carlo_linear visited in part order, as many times as a statistic needs passes
// (a mean before the spread about it): kept in memory up to `kept` parts, beyond that
// machined again block by block for each visit (the same numbers: every part has its own stream),
// so the memory stays bounded whatever the number of parts, at the cost of machining them again.
class LinearParts {
 public:
  static constexpr std::size_t kKeptParts = std::size_t{1} << 17;  // 5 MB
  static constexpr std::size_t kBlock = std::size_t{1} << 16;      // a multiple of the chunk
  // block: parts machined at a time when they are not kept (rounded up to whole chunks).
  LinearParts(const GaugingProcess& p, const LinearGauge& g, double threshold_V, std::size_t parts,
              std::uint64_t seed, std::size_t kept = kKeptParts, std::size_t block = kBlock)
      : p_(p),
        g_(g),
        threshold_V_(threshold_V),
        parts_(parts),
        seed_(seed),
        kept_(kept),
        block_((std::max<std::size_t>(block, 1) + kLinearPartChunk - 1) / kLinearPartChunk *
               kLinearPartChunk) {}
  [[nodiscard]] std::size_t size() const noexcept { return parts_; }
  // f(std::size_t part, const PartResult&) for every part, in order.
  template <class F>
  void for_each(F&& f) {
    if (parts_ <= kept_) {
      if (all_.size() != parts_) all_ = monte_carlo_linear(p_, g_, threshold_V_, parts_, seed_);
      for (std::size_t i = 0; i < parts_; ++i) f(i, all_[i]);
      return;
    }
    std::vector<PartResult> block(std::min(block_, parts_));
    for (std::size_t first = 0; first < parts_; first += block_) {
      const std::span<PartResult> b(block.data(), std::min(block_, parts_ - first));
      monte_carlo_linear(p_, g_, threshold_V_, first, b, seed_);
      for (std::size_t i = 0; i < b.size(); ++i) f(first + i, b[i]);
    }
  }

 private:
  GaugingProcess p_;
  LinearGauge g_;
  double threshold_V_;
  std::size_t parts_;
  std::uint64_t seed_;
  std::size_t kept_, block_;
  std::vector<PartResult> all_;
};

// The first-passage bias of (23) (study.cpp says why no closed form serves): the linearised
// parts' mean error, made precise by the control variate ε(t*)/K (mean 0, following the finished
// size closely): mean(e) − c·mean(ε*/K), c their regression slope, with its standard error. Over
// the parts that tripped before the backstop with ε(t*) known, in three passes (the means; the
// spread and covariance about them; the residuals), each summing in part order.
struct FirstPassageBias {
  double bias_m = 0.0;
  double standard_error_m = 0.0;
};
FirstPassageBias first_passage_bias(LinearParts& parts, double target_m, double gain_V_per_m);

// Samples of the filter-output noise ε, n apart by `spacing_s`, from one long exact path:
// for checking (25) by Monte Carlo.
std::vector<double> filter_noise_samples(const GaugingProcess& p, const LinearGauge& g,
                                         std::size_t n, double spacing_s, std::uint64_t seed);

// Full electromechanical model for one part: x(t) + ξ(t) moves the contact surface; the relay
// acts on the simulated S(t): the transducer's generator signal through the machine side
// (rectifier, filter, relay and backstop of control::GaugeMachine). Optionally records (time,
// x, S, probe z) every `record_every`.
PartResult machine_part_full(const GaugingProcess& p, const sensors::VibroContactGauge::Params& gp,
                             double step_s, double threshold_V, std::uint64_t seed,
                             sim::Recorder* rec = nullptr, std::size_t record_every = 50,
                             double max_time_s = 0.0);

// Full model, static calibration at fixed x (no removal, no noise): the settled mean of S and
// its ripple (half the peak-to-peak left by the filter on the rectified signal).
struct SignalLevel {
  double mean_V = 0.0;
  double ripple_V = 0.0;
};
SignalLevel full_model_signal(const sensors::VibroContactGauge::Params& gp, double step_s,
                              double x_m, double settle_s = 0.8, double average_s = 0.4);
inline double full_model_mean_signal(const sensors::VibroContactGauge::Params& gp, double step_s,
                                     double x_m, double settle_s = 0.8, double average_s = 0.4) {
  return full_model_signal(gp, step_s, x_m, settle_s, average_s).mean_V;
}

// threshold = "calibrated_dynamic" (calibration.cpp): machine parts with the full model (noise
// included), each at the current S_th, and move S_th by K·(mean finished − target) after each
// batch, the errors pooled (each corrected to the current S_th through the slope K). Batches of 8
// parts with noise (1 without); stops when the pooled mean is within its standard error of the
// target and that error is below `precision_m`, or at max_parts. Without noise each part is
// exact: the threshold is bracketed and narrowed (regula falsi) until the part finishes within
// precision_m (at most 0.05 µm) of the target, or at max_parts. The study calls it without noise, aimed at target − the linearised
// model's first-passage bias (study.cpp says why).
struct DynamicCalibration {
  double threshold_V = 0.0;
  std::size_t parts = 0;      // parts machined
  double mean_error_m = 0.0;  // pooled, at the final threshold
  double standard_error_m = 0.0;
  bool converged = false;
  // Without noise, not converged: the finished size's jump across the target between the two
  // thresholds bracketing it (0 otherwise).
  double jump_m = 0.0;
  double bracket_V = 0.0;  // the two thresholds' distance then
};
DynamicCalibration calibrate_dynamic(const GaugingProcess& p,
                                     const sensors::VibroContactGauge::Params& gp, double dt,
                                     double threshold0_V, double gain_V_per_m,
                                     std::size_t max_parts, double precision_m, std::uint64_t seed,
                                     double max_time_s);

// The size threshold a machine runs with, for the study's parts and lathectl_gauge alike (one
// derivation: LinuxCNC ran the plan's while run aimed past the bias, +0.11 µm at σ = 3 µm): the
// plan's (23); calibrated with noise, (23) on the calibrated line aimed at target − the
// first-passage bias of d.parts linearised parts (streams from `seed` + 1000003, study.cpp says
// why); calibrated_dynamic, that moved until the full model's noiseless part finishes at
// target − the bias (calibrate_dynamic, `seed` + 17). p: the process with its cycle.
struct MachineThreshold {
  double threshold_V = 0.0;
  double static_V = 0.0;   // before the dynamic calibration
  FirstPassageBias bias;   // zero unless calibrated with noise
  DynamicCalibration dyn;  // calibrated_dynamic only
};
MachineThreshold machine_threshold(const Settings& d, const GaugingProcess& p,
                                   const ThresholdPlan& plan, double dt, std::uint64_t seed,
                                   double max_time_s,
                                   std::size_t kept = LinearParts::kKeptParts);

// One full-model part without noise for a transducer variant, with its own calibrated (23)
// (no bias: no noise): the finished error, and the probe's Poincaré spread and the signal's
// ripple at the trip point — the study's table of what causes the full model's error.
struct NoiselessPart {
  double error_m = 0.0;
  double spread_m = 0.0;
  double ripple_V = 0.0;
};
NoiselessPart noiseless_part(const GaugingProcess& quiet,
                             const sensors::VibroContactGauge::Params& gp, double dt,
                             std::uint64_t seed, double max_time_s);

}  // namespace lathectl::systems::d_gauging
