// System A's regulator studies (regulator_studies.hpp).
#include "systems/a_pulse_feed/regulator_studies.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "lathectl/core/first_order_lag.hpp"
#include "systems/a_pulse_feed/metrics.hpp"

namespace lathectl::systems::a_pulse_feed {

namespace {
using io::fmt;
using io::json_number;
using nlohmann::json;

// 95th percentile of |x|.
double p95_abs(std::vector<double> x) {
  if (x.empty()) return std::nan("");
  for (double& v : x) v = std::abs(v);
  std::sort(x.begin(), x.end());
  return x[static_cast<std::size_t>(std::floor(0.95 * static_cast<double>(x.size() - 1)))];
}
double share_within(const std::vector<double>& x, double tol) {
  if (x.empty()) return std::nan("");
  double n = 0.0;
  for (double v : x) n += std::abs(v) <= tol ? 1.0 : 0.0;
  return n / static_cast<double>(x.size());
}

struct Errors {
  std::vector<double> pulsed, throttle;  // relative flow errors
};

// One Monte Carlo: `sources` says which errors are drawn (slot, diameter, μ, lap, switching).
Errors draw(const Settings& st, const ToleranceStudy& t, double slot, double gap, double q_nom,
            std::uint64_t seed, const std::array<bool, 5>& sources) {
  const auto& a = st.rig;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Errors e;
  e.pulsed.reserve(t.samples);
  e.throttle.reserve(t.samples);
  for (std::size_t i = 0; i < t.samples; ++i) {
    // Every draw is taken whether used or not: each source sees the same numbers in every study.
    const double dh = n01(rng) * t.slot_sigma_m, dd = n01(rng) * t.diameter_sigma_m,
                 dmu = n01(rng) * t.mu_sigma, dlap = n01(rng) * t.lap_sigma_m,
                 dsw_o = n01(rng) * t.switching_sigma, dsw_c = n01(rng) * t.switching_sigma;
    auto p = a.regulator;
    if (sources[1]) p.orifice.spool_diameter_m += dd;
    if (sources[2]) p.orifice.discharge_coefficient = std::clamp(p.orifice.discharge_coefficient * (1.0 + dmu), 0.05, 1.0);
    if (sources[3]) p.lap_m = std::max(p.lap_m + dlap, 0.0);
    if (sources[4]) {
      p.opening_time_s = std::max(p.opening_time_s * (1.0 + dsw_o), 0.0);
      p.closing_time_s = std::max(p.closing_time_s * (1.0 + dsw_c), 0.0);
    }
    const double h = std::clamp(slot + (sources[0] ? dh : 0.0), 0.0, p.max_slot_m);
    const double q = regulator_characteristic(p, h, a.frequency_Hz, {a.pulse_width_s}, 6).front();
    e.pulsed.push_back(q / q_nom - 1.0);
    hydraulics::Throttle thr;
    thr.configure({p.orifice, {}});  // no silting here: a new throttle
    const double qt = thr.step(1.0, std::max(gap + (sources[0] ? dh : 0.0), 0.0));
    e.throttle.push_back(qt / q_nom - 1.0);
  }
  return e;
}
}  // namespace

std::string characteristic_study(const Settings& st, double slot_m, double frequency_Hz,
                                 io::RunOutput& out) {
  const auto& rp = st.rig.regulator;
  const double h = slot_m, f = frequency_Hz;
  std::vector<double> widths, duty;
  for (int k = 0; k <= 40; ++k) {
    duty.push_back(k / 40.0);
    widths.push_back(k / 40.0 / f);
  }
  auto ideal_p = rp;
  ideal_p.opening_time_s = ideal_p.closing_time_s = ideal_p.lap_m = 0.0;
  const auto q_real = regulator_characteristic(rp, h, f, widths);
  const auto q_ideal_sim = regulator_characteristic(ideal_p, h, f, widths);
  io::Plot ch{"Regulator characteristic at h = " + fmt(h * 1e6) + " µm, f = " + fmt(f) + " Hz",
              "duty Δt/T",
              "mean flow [cm³/min]",
              {},
              {}};
  io::Series formula{"formula (1): μπd·h·√(2Δp/ρ)·Δt/T", duty, {}, "#555", true, false};
  for (double d : duty) formula.y.push_back(rp.orifice.gain_per_m() * h * d * 6e7);
  io::Series ideal{"simulated, instantaneous switching", duty, {}, "#2ca02c", false, true};
  for (double q : q_ideal_sim) ideal.y.push_back(q * 6e7);
  io::Series real{"simulated, opening " + fmt(rp.opening_time_s * 1e3) + " ms / closing " +
                      fmt(rp.closing_time_s * 1e3) + " ms, overlap " + fmt(rp.lap_m * 1e6) + " µm",
                  duty,
                  {},
                  "#1f77b4",
                  false,
                  false};
  for (double q : q_real) real.y.push_back(q * 6e7);
  ch.series = {formula, ideal, real};
  out.report.plots.push_back(ch);
  double worst = 0.0;
  for (std::size_t k = 1; k < duty.size() - 1; ++k)
    worst =
        std::max(worst, std::abs(q_ideal_sim[k] / (rp.orifice.gain_per_m() * h * duty[k]) - 1.0));
  json& m = out.summary["metrics"];
  m["regulator_ideal_flow_max_error_pct"] = 100.0 * worst;
  // Dead zone and saturation from the switching model, closed form against simulation:
  //   no flow while Δt < lap/v_open;  full flow once T − Δt < (h + lap)/v_close.
  const double travel = rp.lap_m + rp.max_slot_m;
  const double dead_theory = rp.opening_time_s * rp.lap_m / travel * f;
  const double sat_theory = 1.0 - rp.closing_time_s * (h + rp.lap_m) / travel * f;
  const auto lim = regulator_switching_limits(rp, h, f);
  const double dead_sim = lim.dead_zone_duty, sat_sim = lim.saturation_duty;
  m["regulator_dead_zone_duty"] = dead_theory;
  m["regulator_dead_zone_duty_simulated"] = dead_sim;
  m["regulator_saturation_duty"] = sat_theory;
  m["regulator_saturation_duty_simulated"] = sat_sim;
  if (!(rp.opening_time_s > 0.0 || rp.closing_time_s > 0.0 || rp.lap_m > 0.0)) return {};
  return "regulator dead zone: no flow below duty " + fmt(dead_theory, "%.3f") +
         " (closed form; simulated " + fmt(dead_sim, "%.5f") +
         "); the spool stops closing between pulses from duty " + fmt(sat_theory, "%.4f") +
         " (closed form; simulated " + fmt(sat_sim, "%.5f") + ")";
}

void tolerance_study(const Settings& st, const ToleranceStudy& t, double slot_m,
                     std::uint64_t seed, io::RunOutput& out, io::Claims& claims) {
  const auto& a = st.rig;
  // Nominal: the pulsed regulator's simulated mean flow, and the throttle gap that gives it.
  const double q_nom =
      regulator_characteristic(a.regulator, slot_m, a.frequency_Hz, {a.pulse_width_s}, 6).front();
  const double gap = q_nom / a.regulator.orifice.gain_per_m();
  const char* names[] = {"slot / gap opening", "spool diameter", "discharge coefficient μ",
                         "spool overlap (pulsed only)", "switching times (pulsed only)"};
  const double sig[] = {t.slot_sigma_m * 1e6, t.diameter_sigma_m * 1e6, t.mu_sigma * 100.0,
                        t.lap_sigma_m * 1e6, t.switching_sigma * 100.0};
  const char* units[] = {" µm", " µm", " %", " µm", " %"};
  io::Table tab{"Manufacturing tolerance: flow error of the pulsed regulator (slot " +
                    fmt(slot_m * 1e6) + " µm, duty " +
                    fmt(a.pulse_width_s * a.frequency_Hz, "%.3f") +
                    ") and of a continuous throttle set for the same flow (gap " +
                    fmt(gap * 1e6, "%.3g") + " µm), " + std::to_string(t.samples) + " samples",
                {"error source (σ)", "pulsed: 95 % of |error| below [%]",
                 "throttle: 95 % of |error| below [%]", "throttle / pulsed",
                 "pulsed within ±" + fmt(t.flow_tolerance * 100) + " %",
                 "throttle within ±" + fmt(t.flow_tolerance * 100) + " %"},
                {}};
  json rows = json::array();
  Errors all;
  for (int k = 0; k <= 5; ++k) {
    std::array<bool, 5> src{};
    for (int j = 0; j < 5; ++j) src[static_cast<std::size_t>(j)] = k == 5 || j == k;
    Errors e = draw(st, t, slot_m, gap, q_nom, seed, src);
    const double pp = p95_abs(e.pulsed), pt = p95_abs(e.throttle);
    const std::string name =
        k == 5 ? std::string("all together") : std::string(names[k]) + " (" + fmt(sig[k]) + units[k] + ")";
    tab.rows.push_back({name, fmt(100 * pp, "%.3g"), fmt(100 * pt, "%.3g"),
                        pp > 0 ? fmt(pt / pp, "%.3g") : "—",
                        fmt(share_within(e.pulsed, t.flow_tolerance), "%.3f"),
                        fmt(share_within(e.throttle, t.flow_tolerance), "%.3f")});
    rows.push_back({{"source", name},
                    {"pulsed_p95_abs_error_pct", json_number(100 * pp)},
                    {"throttle_p95_abs_error_pct", json_number(100 * pt)},
                    {"pulsed_share_within_tolerance", json_number(share_within(e.pulsed, t.flow_tolerance))},
                    {"throttle_share_within_tolerance",
                     json_number(share_within(e.throttle, t.flow_tolerance))}});
    if (k == 5) all = std::move(e);
  }
  const double pp = p95_abs(all.pulsed), pt = p95_abs(all.throttle);
  out.summary["tolerance_study"] = {
      {"nominal_flow_cm3_per_min", json_number(q_nom * 6e7)},
      {"pulsed_slot_um", json_number(slot_m * 1e6)},
      {"throttle_gap_um", json_number(gap * 1e6)},
      // Slot error alone, linear: δQ/Q = δh/h. The opening tolerance for the flow tolerance.
      {"pulsed_slot_tolerance_um", json_number(t.flow_tolerance * slot_m * 1e6)},
      {"throttle_gap_tolerance_um", json_number(t.flow_tolerance * gap * 1e6)},
      {"by_source", rows}};
  out.report.tables.push_back(tab);
  // CDF of |error|, all sources.
  io::Plot cdf{"Manufacturing tolerance: share of regulators within a flow error (all sources)",
               "|flow error| [%]", "share of regulators", {}, {}};
  for (int w = 0; w < 2; ++w) {
    std::vector<double> x = w == 0 ? all.pulsed : all.throttle;
    for (double& v : x) v = 100.0 * std::abs(v);
    std::sort(x.begin(), x.end());
    io::Series s{w == 0 ? "pulsed regulator" : "continuous throttle", {}, {},
                 w == 0 ? "#1f77b4" : "#d62728", false, false};
    for (std::size_t i = 0; i < x.size(); ++i) {
      s.x.push_back(x[i]);
      s.y.push_back(static_cast<double>(i + 1) / static_cast<double>(x.size()));
    }
    cdf.series.push_back(s);
  }
  out.report.plots.push_back(cdf);
  claims.check("manufacturing tolerance (advantage 5): 95 % of |flow error| over the same "
               "machining errors, continuous throttle / pulsed regulator (≥ 2: \"far less "
               "precision\"; " + fmt(100 * pt, "%.3g") + " % against " + fmt(100 * pp, "%.3g") +
               " %; gap " + fmt(gap * 1e6, "%.3g") + " µm against slot " + fmt(slot_m * 1e6) +
               " µm)",
               pt / pp, io::Compare::AtLeast, 2.0);
  claims.note("the tolerance the flow tolerance ±" + fmt(t.flow_tolerance * 100) +
              " % allows on the opening alone (δQ/Q = δh/h): ±" +
              fmt(t.flow_tolerance * slot_m * 1e6, "%.3g") + " µm on the pulsed slot, ±" +
              fmt(t.flow_tolerance * gap * 1e6, "%.3g") +
              " µm on the throttle gap; the pulsed regulator's own precision demands are its "
              "overlap and switching times (rows of the table)");
}

namespace {
// The regulators alone over a duration, in steps of a quarter pulse period (exact within a step:
// closed-form segments), and the flow drift of each: last 5 % against 5–10 % (feed_drift_pct's
// definition).
struct AloneOverTheRun {
  double slot_m, gap_m, frequency_Hz, width_s, duration_s;
  [[nodiscard]] double dt() const { return 0.25 / frequency_Hz; }
  [[nodiscard]] std::size_t steps() const {
    return static_cast<std::size_t>(std::ceil(duration_s / dt()));
  }
  // The drift of a run of n flows, summed as they come (no run held: a 4-hour run at a fast
  // pulse rate is 10⁸ flows): the window of sample i is decided by i/n alone.
  struct Drift {
    std::size_t n;
    double early = 0.0, late = 0.0, ne = 0.0, nl = 0.0;
    void add(std::size_t i, double q) {
      const double x = static_cast<double>(i) / static_cast<double>(n);
      if (x >= 0.05 && x < 0.10) early += q, ne += 1.0;
      if (x >= 0.95) late += q, nl += 1.0;
    }
    [[nodiscard]] double pct() const {
      return 100.0 * (late / nl - early / ne) / (early / ne);
    }
  };
  [[nodiscard]] double pulsed_drift(const hydraulics::PulseRegulator::Params& p) const {
    hydraulics::PulseRegulator reg;
    reg.configure(p);
    Drift d{steps()};
    for (std::size_t i = 0; i < d.n; ++i) d.add(i, reg.step(dt(), slot_m, frequency_Hz, width_s));
    return d.pct();
  }
  [[nodiscard]] double throttle_drift(const hydraulics::PulseRegulator::Params& p) const {
    hydraulics::Throttle thr;
    thr.configure({p.orifice, p.obliteration});
    Drift d{steps()};
    for (std::size_t i = 0; i < d.n; ++i) d.add(i, thr.step(dt(), gap_m));
    return d.pct();
  }
  // Closed form (below the critical gap): the layer grows while the slot is open (≈ Δt a period,
  // g = 1 − e^(−Δt/τ)) and a stroke removes η of it, so after each pulse
  //   δ_{k+1} = (1 − η)·δ_k + (δ_max − (1 − η)·δ_k)·g  →  δ* = δ_max·g/(η + (1 − η)·g),
  // δ(t) = δ*·(1 − r^(t/T)), r = (1 − η)(1 − g) (δ_max·(1 − e^(−duty·t/τ)) at η = 0). The flow is
  // scaled by 1 − 2δ/h: the drift between the windows' middles (7.5 % and 97.5 % of the run).
  [[nodiscard]] double closed_form_drift(const hydraulics::ObliterationParams& ob,
                                         double eta) const {
    const double g = core::FirstOrderLag(width_s, ob.time_constant_s).gain();  // the orifice's
    const double r = (1.0 - eta) * (1.0 - g);
    const double d_star = g * ob.layer_max_m / (eta + (1.0 - eta) * g);
    const double T = 1.0 / frequency_Hz;
    auto layer = [&](double time) {
      return slot_m >= ob.critical_gap_m ? 0.0 : d_star * (1.0 - std::pow(r, time / T));
    };
    const double q_early = std::max(1.0 - 2.0 * layer(0.075 * duration_s) / slot_m, 0.0);
    const double q_late = std::max(1.0 - 2.0 * layer(0.975 * duration_s) / slot_m, 0.0);
    return 100.0 * (q_late - q_early) / q_early;
  }
};

// Where the advantage ends: no sweeping at all (η = 0) and thicker layers.
void no_sweep_by_layer(const Settings& st, const AloneOverTheRun& alone, io::RunOutput& out) {
  io::Table layers{"Worst case, no sweeping (η = 0): flow drift against the layer δ_max per wall",
                   {"δ_max [µm]", "pulsed flow drift [%]", "throttle flow drift [%]",
                    "pulsed keeps its flow (|drift| < 1 %)", "throttle / pulsed drift"},
                   {}};
  json layer_rows = json::array();
  for (const double dm : st.obliteration_layer_m) {
    auto p = st.rig.regulator;
    p.obliteration.removal_per_stroke = 0.0;
    p.obliteration.layer_max_m = dm;
    const double dp = alone.pulsed_drift(p);
    const double dtr = alone.throttle_drift(p);
    layers.rows.push_back({fmt(dm * 1e6), fmt(dp, "%.3g"), fmt(dtr, "%.3g"),
                           std::abs(dp) < 1.0 ? "yes" : "no",
                           dp != 0.0 ? fmt(dtr / dp, "%.3g") : "—"});
    layer_rows.push_back({{"layer_um", dm * 1e6},
                          {"pulsed_flow_drift_pct", json_number(dp)},
                          {"throttle_flow_drift_pct", json_number(dtr)}});
  }
  if (layer_rows.empty()) return;
  out.summary["obliteration_study"]["no_sweep_by_layer"] = layer_rows;
  out.report.tables.push_back(layers);
}

void obliteration_note(const hydraulics::ObliterationParams& ob, const AloneOverTheRun& alone,
                       double eta_min_holding, io::Claims& claims) {
  const double slot_m = alone.slot_m, gap_m = alone.gap_m;
  const double loss_slot = 100.0 * std::min(2.0 * ob.layer_max_m / slot_m, 1.0);
  const double loss_gap = 100.0 * std::min(2.0 * ob.layer_max_m / gap_m, 1.0);
  claims.note(
      "assumption, not finding: \"the pulsed regulator does not silt up\" rests on model "
      "choices, not on a measurement. (1) A closing stroke sweeps off the share η of the layer "
      "([regulator.obliteration] removal_per_stroke, 1 by default; no source gives it): in this "
      "sweep the pulsed flow holds within 1 % over the run " +
      (eta_min_holding == 0.0 ? std::string("for every η, down to 0")
                              : "for η ≥ " + fmt(eta_min_holding, "%.3g")) +
      ". (2) The layer grows only while oil flows through the gap, so a pulsed slot silts only "
      "over its open time (the duty Δt/T of the run). (3) Its slot is 1/duty wider than the "
      "throttle's gap for the same flow (" + fmt(slot_m * 1e6, "%.3g") + " against " +
      fmt(gap_m * 1e6, "%.3g") + " µm): with no sweeping at all (η = 0) a layer of δ_max = " +
      fmt(ob.layer_max_m * 1e6) + " µm per wall finally costs it 2δ_max/h = " +
      fmt(loss_slot, "%.3g") + " % of its flow against the throttle's " + fmt(loss_gap, "%.3g") +
      " %. Then the advantage is the wider slot, not the pulsing, and it ends for layers of a "
      "few % of the slot (the η = 0 table: drift beyond 1 % over the run) and is gone at "
      "δ_max ≈ h/2 = " + fmt(slot_m * 1e6 / 2.0, "%.3g") + " µm, or for a slot built as small "
      "as the throttle's gap. Slots at or above the critical gap (" +
      fmt(ob.critical_gap_m * 1e6) + " µm here) do not silt at all in this model");
}
}  // namespace

void obliteration_study(const Settings& st, double slot_m, double gap_m, double duration_s,
                        io::RunOutput& out, io::Claims& claims) {
  const auto& a = st.rig;
  const auto& ob = a.regulator.obliteration;
  const AloneOverTheRun alone{slot_m, gap_m, a.frequency_Hz, a.pulse_width_s, duration_s};
  const double thr_drift = alone.throttle_drift(a.regulator);
  io::Table tab{"Obliteration against the share η of the layer a closing stroke removes "
                "(regulators alone, " + fmt(duration_s / 60.0) + " min; layer " +
                    fmt(ob.layer_max_m * 1e6) + " µm per wall, τ = " +
                    fmt(ob.time_constant_s / 60.0) + " min, critical gap " +
                    fmt(ob.critical_gap_m * 1e6) + " µm)",
                {"η", "pulsed flow drift [%]", "closed form (layer at the windows' middles) [%]",
                 "throttle flow drift [%]", "pulsed keeps its flow (|drift| < 1 %)"},
                {}};
  io::Plot plot{"Pulsed regulator's flow drift against η (the throttle's for reference)",
                "log10 η (share removed per closing stroke)", "flow drift over the run [%]", {}, {}};
  io::Series sp{"pulsed regulator", {}, {}, "#1f77b4", false, true};
  io::Series thr{"continuous throttle", {}, {}, "#d62728", true, false};
  json rows = json::array();
  double eta_min_holding = std::nan("");
  for (const double eta : st.obliteration_removal) {
    auto p = a.regulator;
    p.obliteration.removal_per_stroke = eta;
    const double d = alone.pulsed_drift(p);
    const double closed = alone.closed_form_drift(ob, eta);
    const bool holds = std::abs(d) < 1.0;
    if (holds && (std::isnan(eta_min_holding) || eta < eta_min_holding)) eta_min_holding = eta;
    tab.rows.push_back({fmt(eta, "%.3g"), fmt(d, "%.3g"), fmt(closed, "%.3g"),
                        fmt(thr_drift, "%.3g"), holds ? "yes" : "no"});
    rows.push_back({{"removal_per_stroke", eta},
                    {"pulsed_flow_drift_pct", json_number(d)},
                    {"pulsed_flow_drift_closed_form_pct", json_number(closed)}});
    if (eta > 0.0) {
      sp.x.push_back(std::log10(eta));
      sp.y.push_back(d);
    }
  }
  if (!sp.x.empty()) {
    const auto [lo, hi] = std::minmax_element(sp.x.begin(), sp.x.end());
    thr.x = {*lo, *hi};
    thr.y = {thr_drift, thr_drift};
  }
  plot.series = {sp, thr};
  out.summary["obliteration_study"] = {
      {"throttle_flow_drift_pct", json_number(thr_drift)},
      {"pulsed_slot_um", json_number(slot_m * 1e6)},
      {"throttle_gap_um", json_number(gap_m * 1e6)},
      {"smallest_removal_keeping_flow", json_number(eta_min_holding)},
      {"by_removal", rows}};
  out.report.tables.push_back(tab);
  no_sweep_by_layer(st, alone, out);
  out.report.plots.push_back(plot);
  obliteration_note(ob, alone, eta_min_holding, claims);
}

}  // namespace lathectl::systems::a_pulse_feed
