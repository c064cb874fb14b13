#include "systems/d_gauging/settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <stdexcept>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "lathectl/sim/config_error.hpp"

namespace lathectl::systems::d_gauging {

namespace {

using io::Param;
using io::Range;
using io::TableReader;
constexpr double kUm = 1e-6;  // µm → m
constexpr double kMs = 1e-3;  // ms → s

// [process]: the controlled size x = m_x − a·t, the disturbance the gauge sees, the relay.
void read_process(TableReader& root, Settings& d) {
  auto pr = root.table("process", true);
  auto& p = d.process;
  pr->require({"allowance_um", {0.0, 1e5, true, false}, "m_x, the allowance at the start", kUm},
              p.allowance_m);
  pr->require({"removal_um_per_s", {0.0, 1e5, true, false}, "a, the removal rate", kUm},
              p.removal_m_per_s);
  pr->require({"target_um", Range::any(), "x_k, the size the relay stops at; < allowance_um", kUm},
              p.target_m);
  pr->check(p.target_m < p.allowance_m, "target_um", "must be below allowance_um");
  double sigma_m = std::sqrt(p.noise_variance_m2);
  pr->read(
      {"noise_sigma_um", Range::closed(0, 1e4), "√D, σ of the disturbance ξ the gauge sees", kUm},
      sigma_m);
  p.noise_variance_m2 = sigma_m * sigma_m;
  pr->read({"noise_beta_per_s", {0.0, 1e6, true, false}, "β in R(τ) = D·e^{−β|τ|}"},
           p.noise_beta_per_s);
  pr->read({"relay_response_ms", Range::closed(0, 1e4), "t_r, the relay's response time", kMs},
           p.relay_response_s);
  // A gauged shop tolerance is microns to millimetres; 0.005 µm is a unit slip (mm for µm?).
  pr->require({.key = "tolerance_um",
               .range = {0.0, 1e5, true, false},
               .doc = "± about the target; for Cp and Cpk",
               .scale = kUm,
               .plausible = Range::closed(0.5, 5000.0)},
              d.tolerance_m);
  // The derived default is set before the read, so the run's settings record shows the value used.
  if (std::isnan(p.backstop_m) && !pr->is_describing()) p.backstop_m = p.target_m - d.tolerance_m;
  pr->read({"backstop_um", Range::any(),
            "the programmed limit position: the cut ends when x reaches it if the relay has not "
            "tripped, with an alarm (absent: target_um − tolerance_um, the lower tolerance limit)",
            kUm},
           p.backstop_m);
  pr->check(p.backstop_m < p.target_m, "backstop_um", "must be below target_um");
  pr->finish();
}

// [transducer]: the electromagnetic vibrator, its probe and contact, the generator and filter.
void read_transducer(TableReader& root, sensors::VibroContactGauge::Params& t) {
  auto tr = root.table("transducer", true);
  tr->require({"supply_V", {0.0, 1e4, true, false}, "supply voltage (amplitude)"}, t.supply_V);
  tr->require({"supply_Hz", {0.0, 1e5, true, false}, "supply frequency; the probe is driven at 2ω"},
              t.supply_Hz);
  tr->require({"coil_turns", {0.0, 1e7, true, false}, "W, the coil's turns"}, t.coil_turns);
  tr->require({"coil_resistance_ohm", {0.0, 1e7, true, false}, "r, the coil's resistance"},
              t.coil_resistance_ohm);
  tr->require({"coil_inductance_H", {0.0, 1e4, true, false}, "L, the coil's inductance"},
              t.coil_inductance_H);
  tr->require({"force_coefficient_N_per_Wb2",
               {0.0, 1e20, true, false},
               "a_f, the magnet's force per flux²"},
              t.force_coefficient_N_per_Wb2);
  tr->require({"probe_mass_g", {0.0, 1e6, true, false}, "M, the probe's moving mass", 1e-3},
              t.probe_mass_kg);
  tr->require({"probe_damping_N_s_per_m", Range::closed(0, 1e6), "h, the probe's damping"},
              t.probe_damping_N_s_per_m);
  tr->require({"probe_stiffness_N_per_mm", {0.0, 1e9, true, false}, "k, the probe's spring", 1e3},
              t.probe_stiffness_N_per_m);
  tr->read({"contact_stiffness_N_per_mm",
            {0.0, 1e9, true, false},
            "k_c, the contact with the part",
            1e3},
           t.contact_stiffness_N_per_m);
  tr->read({"contact_damping_N_s_per_m", Range::closed(0, 1e6), "c_c, the contact's damping"},
           t.contact_damping_N_s_per_m);
  tr->require(
      {"generator_V_per_m_per_s", {0.0, 1e6, true, false}, "K_g, the velocity generator's gain"},
      t.generator_V_per_m_per_s);
  tr->read({"generator_time_constant_ms", Range::closed(0, 1e4), "T_g, the generator's lag", kMs},
           t.generator_time_constant_s);
  tr->require({"filter_time_constant_ms",
               {0.0, 1e6, true, false},
               "T_f, the filter after the rectifier",
               kMs},
              t.filter_time_constant_s);
  using F = sensors::VibroContactGauge::Params::Filter;
  const std::string filter =
      tr->pick({"filter",
                {},
                "the filter after the rectifier: the seed's first-order lag T_f (14), two lags "
                "T_f/2 in cascade (second_order: the same ramp lag, the 2ω ripple far lower), or "
                "the mean over the even number of supply periods nearest 2·T_f (synchronous: "
                "every harmonic of the half supply frequency nulled)"},
               {"first_order", "second_order", "synchronous"}, "first_order");
  t.filter = filter == "second_order"  ? F::SecondOrder
             : filter == "synchronous" ? F::Synchronous
                                       : F::FirstOrder;
  tr->read({"magnet_gap_mm", Range::closed(0, 1e4),
            "δ, the electromagnet's effective air gap at rest in (6) Φ = (L·i/W)·δ/(δ − z); "
            "0: the seed's linear coil Φ = L·i/W (consistent with (5) and L: δ = W²/(2·a_f·L))",
            1e-3},
           t.magnet_gap_m);
  tr->read({"pm_force_N", Range::closed(0, 1e4),
            "F_M0, the permanent magnet's pull on the probe at rest, (9)-(10) F_M = a₂·Φ_M²"},
           t.pm_force_N);
  tr->read({"pm_gap_mm", Range::closed(0, 1e4),
            "b₂, the permanent magnet's gap in (11) Φ_M = b₁/(b₂ − z): F_M = F_M0·(b₂/(b₂ − z))² "
            "and the generator's gain K_g·(b₂/(b₂ − z))²; 0: linear generator, constant F_M",
            1e-3},
           t.pm_gap_m);
  tr->finish();
}

// [sequence]: rough → fine → spark-out before size, each a threshold of its own from (23).
void read_sequence(TableReader& root, Settings& d) {
  auto t = root.table("sequence");
  if (!t) return;
  auto& q = d.sequence;
  q.enabled = true;
  t->read({"rough_factor", Range::closed(1, 1e3),
           "the rough step's removal rate / process.removal_um_per_s"},
          q.rough_factor);
  t->read({"fine_factor", Range::closed(1, 1e3),
           "the fine step's removal rate / process.removal_um_per_s; ≤ rough_factor"},
          q.fine_factor);
  t->check(q.fine_factor <= q.rough_factor, "fine_factor", "must not exceed rough_factor");
  t->read({"fine_um", {0.0, 1e5, true, false}, "the size above target where fine starts", kUm},
          q.fine_m);
  t->read({"spark_um", {0.0, 1e5, true, false},
           "the size above target where spark-out (the size step's rate) starts; < fine_um", kUm},
          q.spark_m);
  t->check(q.spark_m < q.fine_m, "spark_um", "must be below fine_um");
  t->check(d.process.target_m + q.fine_m < d.process.allowance_m, "fine_um",
           "must end before the allowance: target_um + fine_um < allowance_um");
  t->finish();
}

// [interruption]: keyways or flats under the probe, and whether the machine bridges them.
void read_interruption(TableReader& root, Settings& d) {
  auto t = root.table("interruption");
  if (!t) return;
  auto& ir = d.process.interruption;
  const std::string kind =
      t->pick({"kind", {}, "keyway (slots) or flats (chords) under the probe"},
              {"keyway", "flats"}, "keyway");
  ir.kind = kind == "flats" ? Interruption::Kind::Flats : Interruption::Kind::Keyway;
  t->read({"count", Range::closed(1, 64), "how many, equally spaced around the part"}, ir.count);
  t->require({"depth_um", {0.0, 1e6, true, false},
              "the keyway's depth, or the flat's at its middle, below the round surface", kUm},
             ir.depth_m);
  if (ir.kind == Interruption::Kind::Keyway || t->is_describing()) {
    double deg = 30.0;
    t->require({"width_deg", {0.0, 180.0, true, false}, "keyway: its angular width"}, deg);
    ir.width_rad = deg * std::numbers::pi / 180.0;
  }
  if (ir.kind == Interruption::Kind::Flats || t->is_describing()) {
    t->require({"part_radius_mm", {0.0, 1e4, true, false}, "flats: the part's radius", 1e-3},
               ir.radius_m);
    t->check(ir.depth_m < ir.radius_m, "depth_um", "must be below part_radius_mm");
  }
  t->read({"spindle_rpm", {0.0, 1e5, true, false}, "the part's speed"}, ir.spindle_rpm);
  t->read({"gate", {},
           "the machine knows where they are (drawing and spindle angle) and bridges the samples "
           "they pass under the probe, and guard_ms after, with the last two supply periods read "
           "on the round surface; false: it reads them as size"},
          ir.gate);
  t->read({"guard_ms", Range::closed(0, 1e4),
           "after each interruption, samples still bridged while the probe settles on the round "
           "surface again",
           kMs},
          ir.guard_s);
  // The bridge replays the two supply periods read on the settled round surface before each
  // interruption: they must fit between one interruption's guard and the next (GaugeMachine
  // alarms gauge_no_round_surface otherwise; gauge_machine.hpp says what happens without).
  t->check(ir.count * 2.0 * ir.half_span_rad() < 2.0 * std::numbers::pi, "count",
           "the interruptions must leave part of the surface round");
  if (t->is_describing()) {
    t->check(true, "spindle_rpm",
             "gate: each interruption and guard_ms must leave two supply periods of round "
             "surface before the next (what the bridge replays)");
  } else if (ir.gate) {
    const double need = 2.0 / d.transducer.supply_Hz;
    const double span = 2.0 * ir.half_span_rad() / (2.0 * std::numbers::pi);  // of a revolution
    const double fastest = 60.0 * (1.0 / ir.count - span) / (need + ir.guard_s);
    char msg[320];
    std::snprintf(msg, sizeof msg,
                  "the interruptions come every %.1f ms: each with its guard_ms leaves %.1f ms of "
                  "settled round surface before the next, less than the two supply periods (%.1f "
                  "ms) the bridge replays; at most %.0f rpm with this guard",
                  1e3 * ir.revolution_s() / ir.count, std::max(0.0, 1e3 * ir.round_stretch_s()),
                  1e3 * need, std::floor(fastest));
    t->check(ir.round_stretch_s() >= need, "spindle_rpm", msg);
  }
  t->finish();
}

// [gauge] and [monte_carlo]: the relay's threshold and the study's sample sizes.
void read_gauge(TableReader& root, Settings& d) {
  if (auto g = root.table("gauge")) {
    d.threshold = g->pick({"threshold",
                           {},
                           "(23) with closed-form A0 and K (seed), (23) with the full model's "
                           "local line and the first-passage bias (calibrated), that adjusted "
                           "by machining full-model parts without noise until one finishes at "
                           "target − that bias (calibrated_dynamic), or a given voltage"},
                          {"seed", "calibrated", "calibrated_dynamic", "given"}, "calibrated");
    g->read({"calibration_parts_max", Range::closed(2, 1e4),
             "calibrated_dynamic: the most full-model parts (without noise) it may machine"},
            d.calibration_parts_max);
    if (d.threshold == "given" || g->is_describing())
      g->require({"threshold_V", Range::any(), "the relay's threshold, only with \"given\""},
                 d.threshold_V);
    g->read({"force_threshold",
             {},
             "run even when the threshold lies outside the signal range the full model reaches "
             "(the backstop then ends the cut)"},
            d.force_threshold);
    g->finish();
  }
  if (auto mc = root.table("monte_carlo")) {
    mc->read({"parts", Range::closed(1, 1e7), "parts of the linearised Monte Carlo"}, d.parts);
    mc->read({"full_parts", Range::closed(0, 1e4), "parts of the full-model Monte Carlo"},
             d.full_parts);
    mc->finish();
  }
}

}  // namespace

const std::array<io::CriterionKey, 2> kAcceptanceKeys{{
    {"min_cpk", "Cpk of the finished sizes", true, 1.33, Range::closed(0, 100),
     "smallest Cpk = min(USL − mean, mean − LSL)/3σ of the Monte Carlo's finished sizes, the "
     "limits target_um ± tolerance_um (default 1.33, a capable process)"},
    {"max_mean_error_um", "|mean finished size − target|", false, 0.0, Range::closed(0, 1e4),
     "largest |mean finished size − target_um| of the Monte Carlo's parts (0: not judged, the "
     "default: Cpk already counts the mean's offset)"},
}};

void configure_transducer(const io::Scenario& sc, sensors::VibroContactGauge& gauge) {
  try {
    sim::configure_as("transducer",
                      {{"step", "run.step_s"},
                       {"magnet_gap_m", "transducer.magnet_gap_mm"},
                       {"pm_gap_m", "transducer.pm_gap_mm"}},
                      [&] { gauge.configure(sc.get<Settings>().transducer, sc.run.step_s); });
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e, "transducer");
  }
}

ThresholdPlan plan_threshold(const Settings& d, double dt) {
  const auto& p = d.process;
  const auto& t = d.transducer;
  // The transducer's A0: the closed form, or simulated with (6), (9)-(11) (as the run's).
  sensors::VibroContactGauge g;
  g.configure(t, dt);
  ThresholdPlan pl;
  const double lag = sensors::VibroContactGauge::filter_lag_s(t) + p.relay_response_s +
                    p.interruption.bridge_lag_s(t.supply_Hz);
  pl.x_trip_m = p.target_m + p.removal_m_per_s * lag;
  pl.seed_line = {g.signal_gain_V_per_m(), g.free_amplitude_m()};
  pl.calibrated_line = design::calibrated_line(t, dt, pl.x_trip_m);
  pl.line = d.threshold == "seed" ? pl.seed_line : pl.calibrated_line;
  pl.threshold_V = d.threshold == "given"
                       ? d.threshold_V
                       : design::threshold_23(pl.line, p.target_m, p.removal_m_per_s, lag);
  // σ_y of (25), extended to the filter, through the line's gain.
  const double sigma_y =
      std::sqrt(p.noise_variance_m2 *
                sensors::VibroContactGauge::filter_noise_factor(t, p.noise_beta_per_s)) *
      std::abs(pl.line.gain_V_per_m);
  pl.range = design::signal_range(t, dt, p.allowance_m, sigma_y);
  pl.largest_target_m = design::size_at_signal(t, dt, pl.range.low_V, 0.0, pl.range.floor_start_m) -
                        p.removal_m_per_s * lag;
  return pl;
}

// The interruption's geometry (rig.hpp): here, so the HAL components that link the settings
// alone have it.
double Interruption::half_span_rad() const {
  if (kind == Kind::Keyway) return 0.5 * width_rad;
  if (kind == Kind::Flats && radius_m > 0.0)
    return std::acos(std::clamp(1.0 - depth_m / radius_m, -1.0, 1.0));
  return 0.0;
}

double Interruption::from_middle_rad(double theta) const {
  const double pitch = 2.0 * std::numbers::pi / count;
  return theta - pitch * std::round(theta / pitch);
}

double Interruption::depth_at(double theta) const {
  if (!under(theta)) return 0.0;
  if (kind == Kind::Keyway) return depth_m;
  // A flat: the chord (R − h) from the axis, at φ from its middle (R − h)/cos φ.
  return radius_m - (radius_m - depth_m) / std::cos(from_middle_rad(theta));
}

double Interruption::round_stretch_s() const {
  const double rev = revolution_s();
  return rev / count - 2.0 * half_span_rad() / (2.0 * std::numbers::pi) * rev - guard_s;
}

double Interruption::bridge_lag_s(double supply_Hz) const {
  if (!any() || !gate) return 0.0;
  const double rev = revolution_s();
  const double span = 2.0 * half_span_rad() / (2.0 * std::numbers::pi) * rev;
  return control::GaugeMachine::bridge_lag_s(span + guard_s, count, rev, supply_Hz);
}

double SpindleAngle::update(double revs, double dt_s) noexcept {
  if (!std::isfinite(revs)) {
    last_ = revs;
    speed_ = 0.0;
    return revs;
  }
  since_ += dt_s;
  if (revs != last_) {
    if (std::isfinite(last_)) {
      speed_ = (revs - last_) / since_;
      interval_ = since_;
    }
    last_ = revs;
    since_ = 0.0;
  }
  return last_ + speed_ * std::min(since_, interval_);
}

GaugingCycle gauging_cycle(const Sequence& s, const design::GaugeLine& line,
                           const GaugingProcess& p, double lag_s, double size_threshold_V) {
  GaugingCycle c;
  if (!s.enabled) return c;
  using Command = control::GaugeMachine::Command;
  const double a = p.removal_m_per_s;
  c.rate_factor = {s.rough_factor, s.fine_factor, 1.0, 1.0};
  c.before = {{design::threshold_23(line, p.target_m + s.fine_m, s.rough_factor * a, lag_s),
               Command::Fine},
              {design::threshold_23(line, p.target_m + s.spark_m, s.fine_factor * a, lag_s),
               Command::SparkOut}};
  if (!(c.before[1].threshold_V < size_threshold_V))
    throw std::invalid_argument("the size threshold " + std::to_string(size_threshold_V) +
                                " V is not above spark-out's (23) threshold " +
                                std::to_string(c.before[1].threshold_V) + " V: lower spark_um");
  return c;
}

std::unique_ptr<io::SystemSettings> read_settings(TableReader& root, io::Scenario& /*sc*/,
                                                  const io::MaterialLibrary& /*lib*/) {
  auto d = std::make_unique<Settings>();
  read_process(root, *d);
  read_transducer(root, d->transducer);
  read_sequence(root, *d);
  read_interruption(root, *d);
  read_gauge(root, *d);
  io::read_acceptance(root, d->acceptance);
  return d;
}

}  // namespace lathectl::systems::d_gauging
