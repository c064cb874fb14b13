// The gauge's machine side against seed 003's formulas: the size at which the relay ends a
// plunge with threshold (23), the filtered noise's variance (25), the relay's response per
// step, the backstop and the sensor checks.
//
// The generator's signal is synthesised so its rectified mean is known exactly: a probe
// oscillating at 2ω with amplitude A − x gives u = (π/2)·K·(A − x)·sin(2ωt), whose |u| has the
// mean K·(A − x) (the seed's linear model: S = K·(A − x) after the filter). Its ripple is the
// Fourier series |sin θ| = 2/π − (4/π)·Σ cos(2kθ)/(4k² − 1).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/core/parameter_error.hpp"

namespace {

using lathectl::control::GaugeMachine;
using lathectl::control::Reason;
using lathectl::sensors::GaugeFilterKind;
using Command = GaugeMachine::Command;

constexpr double kK = 1e4;          // V/m
constexpr double kA = 300e-6;       // free amplitude A0
constexpr double kAllow = 200e-6;   // x at the start
constexpr double kRate = 20e-6;     // a, m/s
constexpr double kTarget = 50e-6;   // x_k
constexpr double kRelay = 0.02;     // t_r
constexpr double kDt = 2e-5;
constexpr double kSupply = 50.0;

GaugeMachine::Params params(GaugeFilterKind kind, std::vector<GaugeMachine::Step> steps) {
  GaugeMachine::Params p;
  p.period_s = kDt;
  p.filter = {kind, 0.1, kSupply};
  p.steps = std::move(steps);
  p.relay_response_s = kRelay;
  p.arm_after_s = 0.5;
  p.free_signal_V = kK * kA;
  p.initial_signal_V = kK * (kA - kAllow);  // settled on the part before the plunge starts
  return p;
}

// (23): S_th = K·(A − x_k − a·(lag + t_r)).
double threshold_23(const GaugeMachine::Params& p) {
  return kK * (kA - kTarget - kRate * (lathectl::sensors::GaugeFilter::lag_s(p.filter) + kRelay));
}

struct Plunge {
  double finished_m = 0.0;
  std::vector<double> trip_s, operate_s;  // per step
  bool backstop = false;
  Reason reason = Reason::None;
};

// The synchronous filter's error bound on a plunge: the window mean of (A − x(s))·|sin| over
// whole periods P of |sin| (the probe's 2ω rectified: P = 1/(4·supply)) is K·(A − x) at its
// middle but for the ramp's covariance with |sin| within a period that the window cuts at an
// arbitrary phase: at most a·(P/2)·mean||sin| − 2/π|/(2/π) in x. Plus the samples: a step late
// (a·dt) for the relay, a step for the sample's label, and the sampled mean of |sin| (250
// samples a period: −1.3e-5 relative, (A − x)·1.3e-5 in x).
double synchronous_bound_m() {
  const double period = 1.0 / (4.0 * kSupply);
  double mad = 0.0;
  constexpr int n = 100000;
  for (int i = 0; i < n; ++i)
    mad += std::abs(std::sin(std::numbers::pi * (i + 0.5) / n) - 2.0 / std::numbers::pi);
  mad /= n;
  return kRate * 0.5 * period * mad / (2.0 / std::numbers::pi) + 2.0 * kRate * kDt +
         1.4e-5 * (kA - kTarget);
}

// A plunge at rate a from kAllow, the removal stopping when the machine says stop.
Plunge plunge(GaugeMachine& m, double t_end = 12.0, double lost_after_s = INFINITY,
              bool nan = false) {
  Plunge r;
  const double w2 = 2.0 * (2.0 * std::numbers::pi * kSupply);
  double stop = INFINITY;
  int seen_steps = 0, seen_trips = 0;
  for (double t = 0.0; t < t_end; t += kDt) {
    const double x = kAllow - kRate * std::min(t, stop);
    GaugeMachine::Input in;
    in.generator_V = 0.5 * std::numbers::pi * kK * (kA - x) * std::sin(w2 * t);
    if (t >= lost_after_s) in.generator_V = nan ? std::nan("") : 0.0;
    in.position_m = kAllow - kRate * std::min(t + kDt, stop);  // at the sample's end
    m.update(in);
    const auto& o = m.output();
    if (o.tripped_steps > seen_trips) {
      r.trip_s.push_back(o.trip_time_s);
      seen_trips = o.tripped_steps;
    }
    if (o.step > seen_steps) {
      r.operate_s.push_back(o.time_s);
      seen_steps = o.step;
    }
    if (o.stop && !std::isfinite(stop)) {
      stop = t + kDt;
      r.backstop = o.backstop;
      r.reason = o.reason;
    }
  }
  r.finished_m = kAllow - kRate * std::min(t_end, stop);
  return r;
}

TEST(GaugeMachine, SynchronousFilterEndsAtThreshold23Size) {
  // The synchronous mean of |u| over whole periods of 2ω is K·(A − x) at the window's middle:
  // the plunge ends at x_k within synchronous_bound_m() (26 nm).
  GaugeMachine m;
  auto p = params(GaugeFilterKind::Synchronous, {{0.0, Command::Size}});
  p.steps[0].threshold_V = threshold_23(p);
  m.configure(p);
  const Plunge r = plunge(m);
  ASSERT_EQ(r.trip_s.size(), 1u);
  EXPECT_EQ(r.reason, Reason::GaugeSize);
  EXPECT_FALSE(r.backstop);
  EXPECT_NEAR(r.finished_m, kTarget, synchronous_bound_m());
  // The command operates t_r after the crossing, on the first sample past it.
  EXPECT_GE(r.operate_s[0], r.trip_s[0] + kRelay - 1e-12);
  EXPECT_LT(r.operate_s[0], r.trip_s[0] + kRelay + kDt + 1e-12);
}

TEST(GaugeMachine, FirstOrderFilterEndsAtThreshold23WithinItsRipple) {
  // The seed's filter (14): S lags the ramp by T_f; what it leaves of |u|'s harmonics at 4kω,
  // K·(A − x)·2/(4k² − 1)/sqrt(1 + (4kωT_f)²), moves the crossing by at most their sum / K.
  GaugeMachine m;
  auto p = params(GaugeFilterKind::FirstOrder, {{0.0, Command::Size}});
  p.steps[0].threshold_V = threshold_23(p);
  m.configure(p);
  const Plunge r = plunge(m);
  const double w = 2.0 * std::numbers::pi * kSupply;
  double ripple_m = 0.0;
  for (int k = 1; k <= 200; ++k)
    ripple_m += (kA - kTarget) * 2.0 / (4.0 * k * k - 1.0) /
                std::hypot(1.0, 4.0 * k * w * 0.1);
  EXPECT_GT(ripple_m, 1e-7);  // the bound is the filter's, not zero
  EXPECT_NEAR(r.finished_m, kTarget, ripple_m + kRate * kDt);
  EXPECT_EQ(r.reason, Reason::GaugeSize);
}

TEST(GaugeMachine, StepsOperateInOrderOneRelayResponseAfterTheirThresholds) {
  // rough → fine → spark-out → size: each command t_r after its crossing, in order.
  GaugeMachine m;
  auto p = params(GaugeFilterKind::Synchronous, {{0.0, Command::Fine},
                                                 {0.0, Command::SparkOut},
                                                 {0.0, Command::Size}});
  const double s23 = threshold_23(p);
  p.steps[0].threshold_V = s23 - kK * 60e-6;  // 60 µm before size
  p.steps[1].threshold_V = s23 - kK * 20e-6;
  p.steps[2].threshold_V = s23;
  m.configure(p);
  const Plunge r = plunge(m);
  ASSERT_EQ(r.trip_s.size(), 3u);
  ASSERT_EQ(r.operate_s.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    if (i > 0) {
      EXPECT_GT(r.trip_s[i], r.trip_s[i - 1]);
    }
    EXPECT_GE(r.operate_s[i], r.trip_s[i] + kRelay - 1e-12);
    EXPECT_LT(r.operate_s[i], r.trip_s[i] + kRelay + kDt + 1e-12);
  }
  // The crossings where the ramp puts them: (S_i/K − A + x0)/a + lag, within the bound.
  const double lag = lathectl::sensors::GaugeFilter::lag_s(p.filter);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(r.trip_s[i], (p.steps[i].threshold_V / kK - kA + kAllow) / kRate + lag,
                synchronous_bound_m() / kRate);
  EXPECT_NEAR(r.finished_m, kTarget, synchronous_bound_m());
  EXPECT_EQ(m.output().command, Command::Size);
  EXPECT_EQ(m.output().step, 3);
}

TEST(GaugeMachine, ACrossingOfALaterThresholdTripsTheEarlierOnesWithIt) {
  // A short allowance: the signal is already above the fine threshold when the relay arms (its
  // upward crossing never comes); spark-out's crossing trips both, the plunge still ends at x_k.
  GaugeMachine m;
  auto p = params(GaugeFilterKind::Synchronous, {{0.0, Command::Fine},
                                                 {0.0, Command::SparkOut},
                                                 {0.0, Command::Size}});
  const double s23 = threshold_23(p);
  p.steps[0].threshold_V = 0.5 * p.initial_signal_V;  // below the signal from the start
  p.steps[1].threshold_V = s23 - kK * 20e-6;
  p.steps[2].threshold_V = s23;
  m.configure(p);
  const Plunge r = plunge(m);
  ASSERT_EQ(r.trip_s.size(), 2u);  // the first report carries both steps
  ASSERT_EQ(r.operate_s.size(), 2u);
  EXPECT_EQ(m.output().step, 3);
  EXPECT_EQ(m.output().command, Command::Size);
  EXPECT_NEAR(r.trip_s[0],
              (p.steps[1].threshold_V / kK - kA + kAllow) / kRate +
                  lathectl::sensors::GaugeFilter::lag_s(p.filter),
              synchronous_bound_m() / kRate);
  EXPECT_NEAR(r.finished_m, kTarget, synchronous_bound_m());
}

TEST(GaugeMachine, UnreachableThresholdEndsAtTheBackstopWithItsAlarm) {
  GaugeMachine m;
  auto p = params(GaugeFilterKind::FirstOrder, {{kK * kA * 1.01, Command::Size}});
  p.backstop_m = kTarget - 10e-6;
  m.configure(p);
  EXPECT_TRUE(m.output().unreachable);
  EXPECT_EQ(m.output().reason, Reason::GaugeUnreachable);
  const Plunge r = plunge(m);
  EXPECT_TRUE(r.backstop);
  EXPECT_EQ(r.reason, Reason::GaugeBackstop);
  EXPECT_TRUE(lathectl::control::is_alarm(r.reason));
  // Stopped on the first sample at or past the limit position.
  EXPECT_LE(r.finished_m, p.backstop_m);
  EXPECT_GT(r.finished_m, p.backstop_m - kRate * kDt - 1e-12);
}

TEST(GaugeMachine, SignalLostHoldsAfterOneSupplyPeriod) {
  for (bool nan : {false, true}) {
    GaugeMachine m;
    auto p = params(GaugeFilterKind::FirstOrder, {{threshold_23(params(
                                                       GaugeFilterKind::FirstOrder, {})),
                                                   Command::Size}});
    p.signal_lost_V = 0.1 * kK * (kA - kAllow);  // a tenth of the contact's signal
    m.configure(p);
    const double lost = 2.0;
    const Plunge r = plunge(m, 4.0, lost, nan);
    EXPECT_EQ(r.reason, nan ? Reason::SensorNotFinite : Reason::GaugeSignalLost);
    EXPECT_TRUE(m.output().alarm);
    EXPECT_TRUE(r.trip_s.empty());
    // Removal stopped one supply period after the last sample at the level (one sample after a
    // NaN): at most a sample after one period from the loss, at least the period less the time
    // |u| spends below the level about a zero of sin(2ωt): 2·asin(level/peak)/(2ω).
    const double removed = kAllow - kRate * lost - r.finished_m;
    if (nan) {
      EXPECT_GT(removed, 0.0);  // the sample at or after the loss, then its step
      EXPECT_LE(removed, kRate * 2.0 * kDt);
    } else {
      const double x = kAllow - kRate * lost;
      const double peak = 0.5 * std::numbers::pi * kK * (kA - x);
      const double below = 2.0 * std::asin(p.signal_lost_V / peak) /
                           (2.0 * 2.0 * std::numbers::pi * kSupply);
      EXPECT_LE(removed, kRate * (1.0 / kSupply + kDt));
      EXPECT_GE(removed, kRate * (1.0 / kSupply - below - kDt));
    }
  }
}

TEST(GaugeMachine, RearmStartsANewPart) {
  GaugeMachine m;
  auto p = params(GaugeFilterKind::Synchronous, {{0.0, Command::Size}});
  p.steps[0].threshold_V = threshold_23(p);
  p.backstop_m = 0.0;
  m.configure(p);
  (void)plunge(m);
  ASSERT_TRUE(m.output().size);
  GaugeMachine::Input in;
  in.generator_V = 1.0;
  in.position_m = 1.0;
  in.rearm = true;
  m.update(in);
  EXPECT_EQ(m.output().step, 0);
  EXPECT_FALSE(m.output().stop);
  EXPECT_FALSE(m.output().armed);
  EXPECT_EQ(m.output().command, Command::Rough);
  EXPECT_NEAR(m.output().time_s, kDt, 1e-15);
}

TEST(GaugeMachine, FilteredNoiseVarianceIsSeed25) {
  // An Ornstein–Uhlenbeck disturbance ξ (R = D·e^{−β|τ|}) through the filter: Var ε = D·K²·f,
  // f = 1/(1 + βT_f) for the seed's first order (25); (βτ + 2)/(2(1 + βτ)²), τ = T_f/2, for two
  // lags. Samples 1 s apart (correlation e^{−5} after the filter); 4000 of them: the variance's
  // standard error is sqrt(2/N) = 2.2 %, the check 4 of them.
  const double D = 4e-12, beta = 5.0, tf = 0.1, dt = 1e-3;
  for (auto kind : {GaugeFilterKind::FirstOrder, GaugeFilterKind::SecondOrder}) {
    GaugeMachine m;
    GaugeMachine::Params p;
    p.period_s = dt;
    p.filter = {kind, tf, 10.0};  // 2ω·dt = 0.02: the machine's sampling check holds
    p.steps = {{1e9, Command::Size}};
    p.initial_signal_V = 1.0;
    m.configure(p);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> n01(0.0, 1.0);
    const double rho = std::exp(-beta * dt), kick = std::sqrt(D * (1.0 - rho * rho));
    double xi = std::sqrt(D) * n01(rng);
    GaugeMachine::Input in;
    for (int k = 0; k < 2000; ++k) {  // settle
      xi = rho * xi + kick * n01(rng);
      in.generator_V = 1.0 + kK * xi;  // 1 V ≫ 6·K·sqrt(D) = 0.12 V: |u| = u
      m.update(in);
    }
    const int n = 4000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 1000; ++k) {
        xi = rho * xi + kick * n01(rng);
        in.generator_V = 1.0 + kK * xi;
        m.update(in);
      }
      const double e = m.output().signal_V - 1.0;
      sum += e;
      sum2 += e * e;
    }
    const double var = (sum2 - sum * sum / n) / (n - 1);
    const double tau = 0.5 * tf;
    const double f = kind == GaugeFilterKind::FirstOrder
                         ? 1.0 / (1.0 + beta * tf)
                         : (beta * tau + 2.0) / (2.0 * (1.0 + beta * tau) * (1.0 + beta * tau));
    const double expected = D * kK * kK * f;
    EXPECT_NEAR(var / expected, 1.0, 4.0 * std::sqrt(2.0 / n)) << static_cast<int>(kind);
  }
}

TEST(GaugeMachine, ConfigureNamesTheParameterItRefuses) {
  auto refuses = [](GaugeMachine::Params p, const char* name) {
    GaugeMachine m;
    try {
      m.configure(p);
      ADD_FAILURE() << "accepted, expected a refusal of " << name;
    } catch (const lathectl::core::ParameterError& e) {
      EXPECT_EQ(e.parameter(), name) << e.what();
    }
  };
  const auto ok = params(GaugeFilterKind::FirstOrder, {{1.0, Command::Fine}, {2.0, Command::Size}});
  GaugeMachine m;
  EXPECT_NO_THROW(m.configure(ok));
  auto p = ok;
  p.steps = {};
  refuses(p, "steps");
  p = ok;
  p.steps[1].threshold_V = 0.5;  // falling
  refuses(p, "steps");
  p = ok;
  p.steps[1].command = Command::SparkOut;  // the last is not size
  refuses(p, "steps");
  p = ok;
  p.period_s = 1e-3;  // 10 samples a period of 2ω at 50 Hz
  refuses(p, "period_s");
  p = ok;
  p.relay_response_s = -1.0;
  refuses(p, "relay_response_s");
  p = ok;
  p.filter.time_constant_s = 0.0;
  refuses(p, "filter_time_constant_s");
  p = ok;
  p.backstop_m = std::nan("");
  refuses(p, "backstop_m");
}

// Interrupted surfaces: while the gate is up (a keyway under the probe, and its guard after) the
// machine feeds its filter the last two supply periods read on the round surface. On a part of
// constant size the signal is periodic with that period, so the bridged filter sees exactly the
// round surface's signal whatever passed under the probe (the probe swinging free over the
// keyway: three times the amplitude here); without the gate the keyway raises S.
TEST(GaugeMachine, BridgedInterruptionsLeaveThePeriodicSignalOfTheRoundSurface) {
  const double w2 = 2.0 * (2.0 * std::numbers::pi * kSupply);
  const double rev = 0.1, keyway = 0.0083;  // 600 rpm, 30°
  for (auto kind : {GaugeFilterKind::FirstOrder, GaugeFilterKind::SecondOrder,
                    GaugeFilterKind::Synchronous}) {
    auto p = params(kind, {{1e9, Command::Size}});
    p.gate_guard_s = 0.01;
    GaugeMachine round, gated, ungated;
    round.configure(p);
    gated.configure(p);
    ungated.configure(p);
    double worst_gated = 0.0, worst_ungated = 0.0;
    int bridged = 0;
    for (int k = 0; k < 100000; ++k) {  // 2 s
      const double t = k * kDt;
      const double clean = 0.5 * std::numbers::pi * kK * (kA - 100e-6) * std::sin(w2 * t);
      // The keyways from 50 ms on: the machine has read two supply periods whole by then.
      const bool gap = t > 0.05 && std::fmod(t, rev) < keyway;
      GaugeMachine::Input in;
      in.generator_V = clean;
      round.update(in);
      in.generator_V = gap ? 3.0 * clean : clean;
      ungated.update(in);
      in.gate = gap;
      gated.update(in);
      if (t < 0.5) continue;  // the filters settled
      bridged += gated.output().bridged;
      const double s = round.output().signal_V;
      worst_gated = std::max(worst_gated, std::abs(gated.output().signal_V - s) / s);
      worst_ungated = std::max(worst_ungated, std::abs(ungated.output().signal_V - s) / s);
    }
    // The replayed samples are the same sine 2000 samples earlier: equal to rounding.
    EXPECT_LT(worst_gated, 1e-9) << static_cast<int>(kind);
    EXPECT_GT(worst_ungated, 0.05) << static_cast<int>(kind);
    // Gate and guard: 18.3 ms of every 100 ms bridged (of the last 1.5 s).
    EXPECT_NEAR(bridged / 75000.0, 0.183, 0.002) << static_cast<int>(kind);
  }
}

// On a plunge the bridges delay the size the filter sees: (23) with their mean delay
// (bridge_lag_s) added to the filter's lag ends the plunge at x_k, as without interruptions,
// within the synchronous filter's bound and the part of a revolution the window's edge cuts.
TEST(GaugeMachine, BridgedPlungeEndsAtThreshold23WithTheBridgeLag) {
  const double w2 = 2.0 * (2.0 * std::numbers::pi * kSupply);
  const double rev = 0.1, keyway = 0.0083, guard = 0.03;
  auto p = params(GaugeFilterKind::Synchronous, {{0.0, Command::Size}});
  p.gate_guard_s = guard;
  const double bridge_lag = GaugeMachine::bridge_lag_s(keyway + guard, 1.0, rev, kSupply);
  // 38.3 ms bridged, shorter than the 40 ms replayed: every bridged sample is 40 ms old.
  EXPECT_NEAR(bridge_lag, 0.0383 * 0.04 / rev, 1e-12);
  p.steps[0].threshold_V =
      kK * (kA - kTarget -
            kRate * (lathectl::sensors::GaugeFilter::lag_s(p.filter) + bridge_lag + kRelay));
  GaugeMachine m;
  m.configure(p);
  double stop = INFINITY;
  for (double t = 0.0; t < 12.0 && !std::isfinite(stop); t += kDt) {
    const double x = kAllow - kRate * t;
    GaugeMachine::Input in;
    const bool gap = std::fmod(t, rev) < keyway;
    in.generator_V = 0.5 * std::numbers::pi * kK * (kA - x + (gap ? 200e-6 : 0.0)) *
                     std::sin(w2 * t);
    in.gate = gap;
    m.update(in);
    if (m.output().stop) stop = t + kDt;
  }
  ASSERT_TRUE(std::isfinite(stop));
  // The window (200 ms) holds two revolutions; the ramp's delay is the bridges' mean only over
  // whole ones, off by at most a·(bridge's delay)·(bridge/window) where the window cuts one.
  const double cut = kRate * 0.04 * (keyway + guard) / 0.2;
  EXPECT_NEAR(kAllow - kRate * stop, kTarget, synchronous_bound_m() + cut);
}

// Flats under the probe, bridged. The synthesised probe touches a flat `depth` deep at its
// middle on a part of radius R at the contact angle: its amplitude grows by the chord's depth
// there, R − (R − depth)/cos φ, and after the flat it swings short (the measured behaviour of the
// resonant probe: an amplitude deficit of half the flat's depth, decaying with τ = 10 ms), so
// u = (π/2)·K·(A − x + extra)·sin(2ωt). With the gate over the flat and a guard of 6τ after it,
// the filter sees only the settled round surface: (23) with the bridges' mean delay ends the
// plunge at x_k within the synchronous filter's bound and the part of a revolution the window's
// edge cuts, whatever the flats' depth and count — while the round stretch between them holds
// the replay's two supply periods. Read as size, the same flats end it elsewhere.
struct Flats {
  int count = 2;
  double depth_m = 100e-6, radius_m = 10e-3, rev_s = 0.4, ring_s = 0.01;
  [[nodiscard]] double half() const { return std::acos(1.0 - depth_m / radius_m); }
  [[nodiscard]] double span_s() const { return 2.0 * half() / (2.0 * std::numbers::pi) * rev_s; }
  // From the nearest flat's middle at time t (the part at angle 2πt/rev_s + θ0).
  [[nodiscard]] double phi(double t, double theta0) const {
    const double pitch = 2.0 * std::numbers::pi / count;
    const double theta = theta0 + 2.0 * std::numbers::pi * t / rev_s;
    return theta - pitch * std::round(theta / pitch);
  }
  [[nodiscard]] bool under(double t, double theta0) const {
    return std::abs(phi(t, theta0)) < half();
  }
  [[nodiscard]] double extra(double t, double theta0) const {
    const double p = phi(t, theta0), h = half();
    if (std::abs(p) < h) return radius_m - (radius_m - depth_m) / std::cos(p);
    const double pitch = 2.0 * std::numbers::pi / count;
    const double since = (p > 0.0 ? p - h : p + pitch - h) / (2.0 * std::numbers::pi) * rev_s;
    return -0.5 * depth_m * std::exp(-since / ring_s);  // swinging short of the part
  }
};

Plunge flats_plunge(GaugeMachine& m, const Flats& f, double theta0, bool gate) {
  Plunge r;
  const double w2 = 2.0 * (2.0 * std::numbers::pi * kSupply);
  double stop = INFINITY;
  for (double t = 0.0; t < 12.0 && !std::isfinite(stop); t += kDt) {
    const double x = kAllow - kRate * t;
    GaugeMachine::Input in;
    in.generator_V =
        0.5 * std::numbers::pi * kK * std::max(0.0, kA - x + f.extra(t, theta0)) *
        std::sin(w2 * t);
    in.gate = gate && f.under(t, theta0);
    in.position_m = kAllow - kRate * (t + kDt);
    m.update(in);
    if (m.output().stop) {
      stop = t + kDt;
      r.backstop = m.output().backstop;
      r.reason = m.output().reason;
    }
  }
  r.finished_m = kAllow - kRate * std::min(stop, 12.0);
  return r;
}

TEST(GaugeMachine, BridgedFlatsEndAtThreshold23WithTheBridgeLag) {
  const double guard = 0.06;
  for (int count : {1, 2})
    for (double depth : {20e-6, 50e-6, 100e-6, 200e-6})
      for (double theta0 : {0.3, 2.0}) {
        Flats f;
        f.count = count;
        f.depth_m = depth;
        auto p = params(GaugeFilterKind::Synchronous, {{0.0, Command::Size}});
        p.gate_guard_s = guard;
        const double bridge = f.span_s() + guard;
        ASSERT_GE(f.rev_s / count - bridge, 2.0 / kSupply);  // the replay fits between them
        const double lag = GaugeMachine::bridge_lag_s(bridge, count, f.rev_s, kSupply);
        p.steps[0].threshold_V =
            kK * (kA - kTarget -
                  kRate * (lathectl::sensors::GaugeFilter::lag_s(p.filter) + lag + kRelay));
        const std::string tag = std::to_string(count) + " flats " +
                                std::to_string(depth * 1e6) + " µm at " + std::to_string(theta0);
        GaugeMachine gated;
        gated.configure(p);
        const Plunge r = flats_plunge(gated, f, theta0, true);
        EXPECT_EQ(r.reason, Reason::GaugeSize) << tag;
        // Two flats: the window (200 ms) holds one pitch whole, the bridges' delay in it is
        // their mean. One: it holds half a revolution, with one bridge or none, off by up to a
        // bridge's longest delay (two replays, 80 ms)·(bridge/window).
        const double cut = count == 2 ? 0.0 : kRate * 0.08 * bridge / 0.2;
        // And what the probe still swings short after the guard reads as size: its mean over a
        // pitch, (depth/2)·τ·e^(−guard/τ)/pitch (12 nm for 200 µm flats).
        const double unsettled = 0.5 * depth * f.ring_s * std::exp(-guard / f.ring_s) /
                                 (f.rev_s / count);
        EXPECT_NEAR(r.finished_m, kTarget, synchronous_bound_m() + cut + unsettled) << tag;
        // Read as size: the filter sees A − x + the extra, its window one pitch whole, and the
        // threshold still allows for the bridges' delay: the part ends large by about the
        // extra's mean over a pitch and a·(that delay) — ten times the gated part's bound and
        // more; within 15 % of it (the extra varies within the probe's periods: it weights
        // |sin| unevenly there, as the ramp does in synchronous_bound_m).
        if (count != 2) continue;
        double mean_extra = 0.0;
        constexpr int n = 200000;
        for (int i = 0; i < n; ++i) mean_extra += f.extra((i + 0.5) / n * f.rev_s / 2.0, 0.0) / n;
        GaugeMachine open;
        open.configure(p);
        const double large = mean_extra + kRate * lag;
        EXPECT_GT(large, 10.0 * synchronous_bound_m()) << tag;
        EXPECT_NEAR(flats_plunge(open, f, theta0, false).finished_m - kTarget, large,
                    0.15 * large)
            << tag;
      }
}

// Interruptions too close together for the bridge (two flats at 600 rpm with a 30 ms guard: 15.5
// ms of round surface between them, the replay needs 40): the armed gauge holds the feed with
// gauge_no_round_surface; before it arms nothing is decided. One flat a revolution leaves enough.
TEST(GaugeMachine, InterruptionsTooCloseForTheBridgeAlarm) {
  auto p = params(GaugeFilterKind::Synchronous, {{1e9, Command::Size}});
  p.gate_guard_s = 0.03;
  Flats dense;
  dense.rev_s = 0.1;
  GaugeMachine m;
  m.configure(p);
  const Plunge r = flats_plunge(m, dense, 0.0, true);
  EXPECT_EQ(r.reason, Reason::GaugeNoRoundSurface);
  EXPECT_FALSE(r.backstop);
  // The first bridge after the arming, at most one flat pitch (50 ms) later.
  EXPECT_LE(kAllow - r.finished_m, kRate * (p.arm_after_s + 0.05 + kDt));
  EXPECT_GT(kAllow - r.finished_m, kRate * p.arm_after_s);
  Flats one = dense;
  one.count = 1;  // 61.5 ms between
  GaugeMachine ok;
  ok.configure(p);
  (void)flats_plunge(ok, one, 0.0, true);
  EXPECT_FALSE(ok.output().alarm);
  EXPECT_EQ(ok.output().reason, Reason::GaugeUnreachable);
}

}  // namespace
