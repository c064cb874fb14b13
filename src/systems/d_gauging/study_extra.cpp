// System D's studies beside the runs (io::Study::extra_studies): the full model outside the
// linear range, the cause of its error, the gauging cycle's steps and the interruption.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "lathectl/control/types.hpp"
#include "lathectl/core/parallel.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "lathectl/sim/config_error.hpp"
#include "systems/d_gauging/rig.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/d_gauging/study_phases.hpp"

namespace lathectl::systems::d_gauging::detail {

void GaugingStudy::extra_studies(io::RunOutput& out, Claims& claims) {
  outside_the_range(out);
  error_cause(out);
  cycle_and_interruption(out, claims);
}

// 3. Outside the range: fast removal, long filter, target near A0 — each with its own (23).
void GaugingStudy::outside_the_range(io::RunOutput& out) const {
  struct Case {
    std::string name;
    GaugingProcess proc;
    sensors::VibroContactGauge::Params tp;
  };
  std::vector<Case> cases;
  Case c{"inside the range (this scenario)", size_step_, d_.transducer};
  cases.push_back(c);
  c = {"fast removal: a × 10", size_step_, d_.transducer};
  c.proc.removal_m_per_s *= 10.0;
  cases.push_back(c);
  c = {"long filter: T_f × 10", size_step_, d_.transducer};
  c.tp.filter_time_constant_s *= 10.0;
  cases.push_back(c);
  c = {"target near A0 (x_k = 0.85·A0)", size_step_, d_.transducer};
  c.proc.target_m = 0.85 * A0_;
  c.proc.allowance_m = 0.97 * A0_;
  c.proc.backstop_m = c.proc.target_m - d_.tolerance_m;  // each case's own limit position
  cases.push_back(c);
  c = {"target near grazing (x_k = 0.02·A0)", size_step_, d_.transducer};
  c.proc.target_m = 0.02 * A0_;
  c.proc.backstop_m = c.proc.target_m - d_.tolerance_m;
  cases.push_back(c);
  Table outside{
      "Full model against the linearised formulas (no noise; threshold (23) with the seed's A0 and "
      "K)",
      {"case", "trip (22)+(23) [s]", "trip, full model [s]", "finished − target, full [µm]",
       "ended by"},
      {}};
  json cases_json = json::array();
  for (const auto& k : cases) {
    const LinearGauge lg = linear_gauge({K_, A0_}, k.tp);
    const double th = threshold_23(lg, k.proc);
    const double t_lin = linear_trip(k.proc, lg, th);
    const double horizon = 3.0 * (k.proc.allowance_m - k.proc.target_m) / k.proc.removal_m_per_s +
                           20.0 * lg.lag_s() + 1.0;
    const auto r = machine_part_full(k.proc, k.tp, dt_, th, sc_.run.seed, nullptr, 50, horizon);
    const double err = (r.finished_m - k.proc.target_m) * kUm;
    outside.rows.push_back({k.name, fmt(t_lin, "%.3f"), fmt(r.trip_s, "%.3f"), fmt(err, "%.2f"),
                            r.backstop ? "backstop (alarm)" : "relay"});
    cases_json.push_back({{"case", k.name},
                          {"trip_linear_s", json_number(t_lin)},
                          {"trip_full_s", json_number(r.trip_s)},
                          {"finished_error_um", json_number(err)},
                          {"backstop", r.backstop}});
  }
  out.summary["outside_range"] = cases_json;
  out.report.tables.push_back(outside);
}

// 3c. The gauging cycle's steps ([sequence]) as the noiseless full-model part met them, and
// the interrupted surface ([interruption]): the same part with the machine reading the gaps
// and flats as size (no gate) beside it bridging them.
void GaugingStudy::cycle_and_interruption(io::RunOutput& out, Claims& claims) const {
  using Command = control::GaugeMachine::Command;
  const auto name = [](Command c) {
    return c == Command::Fine ? "fine" : c == Command::SparkOut ? "spark-out" : "size";
  };
  if (!p_.cycle.before.empty()) {
    Table t{"The gauging cycle: each step's threshold (23) and the size where its command "
            "operated (full model, no noise)",
            {"step", "threshold [V]", "planned size [µm]", "full model [µm]", "− planned [µm]"},
            {}};
    json cj = json::array();
    const std::array<double, 2> planned{p_.target_m + d_.sequence.fine_m,
                                        p_.target_m + d_.sequence.spark_m};
    double last = INFINITY;
    bool in_order = true;
    for (std::size_t i = 0; i < p_.cycle.before.size(); ++i) {
      const double at = full_.step_at_m[i];
      in_order = in_order && at < last;
      last = at;
      t.rows.push_back({name(p_.cycle.before[i].command), fmt(p_.cycle.before[i].threshold_V),
                        fmt(planned[i] * kUm), fmt(at * kUm, "%.2f"),
                        fmt((at - planned[i]) * kUm, "%.2f")});
      cj.push_back({{"step", name(p_.cycle.before[i].command)},
                    {"threshold_V", json_number(p_.cycle.before[i].threshold_V)},
                    {"planned_um", json_number(planned[i] * kUm)},
                    {"size_um", json_number(at * kUm)}});
    }
    t.rows.push_back({"size", fmt(s_th_), fmt(p_.target_m * kUm),
                      fmt(full_.finished_m * kUm, "%.2f"), fmt(full_err_um_, "%.2f")});
    cj.push_back({{"step", "size"},
                  {"threshold_V", json_number(s_th_)},
                  {"planned_um", json_number(p_.target_m * kUm)},
                  {"size_um", json_number(full_.finished_m * kUm)}});
    out.summary["cycle"] = cj;
    out.report.tables.push_back(t);
    claims.check("gauging cycle: the steps operated in order, each at a smaller size (1: yes)",
                 in_order && full_.finished_m < last ? 1.0 : 0.0, Compare::AtLeast, 1.0);
    // Each earlier step: (23) at its own rate on the same line. It only changes the feed, so
    // it is held to a tenth of the length of the step it starts (fine: fine_um − spark_um;
    // spark-out: spark_um), where the size step is held to a tenth of the tolerance. The static
    // line, fitted at rest, misses more at the faster feeds (the probe's amplitude lags more).
    const std::array<double, 2> length{d_.sequence.fine_m - d_.sequence.spark_m,
                                       d_.sequence.spark_m};
    for (std::size_t i = 0; i < p_.cycle.before.size(); ++i)
      claims.check(std::string("gauging cycle: ") + name(p_.cycle.before[i].command) +
                       " starts at its planned size, full model − planned [µm] (|·| ≤ " +
                       fmt(0.1 * length[i] * kUm) + ", a tenth of the step)",
                   (full_.step_at_m[i] - planned[i]) * kUm, Compare::Within,
                   0.1 * length[i] * kUm);
  }
  const auto& ir = p_.interruption;
  if (ir.any()) {
    // The same noiseless part read without the machine's gate (the seed's relay alone).
    auto open = quiet_;
    open.interruption.gate = false;
    const auto ungated =
        machine_part_full(open, d_.transducer, dt_, s_th_, sc_.run.seed, nullptr, 50,
                          sc_.run.duration_s);
    const double ungated_um = (ungated.finished_m - p_.target_m) * kUm;
    const double bridge = ir.bridge_lag_s(d_.transducer.supply_Hz);
    out.summary["interruption"] = {
        {"kind", ir.kind == Interruption::Kind::Flats ? "flats" : "keyway"},
        {"count", ir.count},
        {"depth_um", json_number(ir.depth_m * kUm)},
        {"span_deg", json_number(2.0 * ir.half_span_rad() * 180.0 / std::numbers::pi)},
        {"spindle_rpm", json_number(ir.spindle_rpm)},
        {"gate", ir.gate},
        {"guard_ms", json_number(ir.guard_s * 1e3)},
        {"bridge_lag_ms", json_number(bridge * 1e3)},
        {"round_stretch_ms", json_number(ir.round_stretch_s() * 1e3)},
        {"finished_error_um", json_number(full_err_um_)},
        {"ungated_finished_error_um", json_number(ungated_um)},
        {"ungated_backstop", ungated.backstop}};
    out.report.tables.push_back(Table{
        "Interrupted surface (no noise, the same threshold): the machine bridging the "
        "interruptions against reading them as size",
        {"machine", "finished − target [µm]", "ended by"},
        {{ir.gate ? "gated (bridged)" : "no gate (this scenario)", fmt(full_err_um_, "%.2f"),
          full_.backstop ? "backstop (alarm)" : "relay"},
         {"no gate", fmt(ungated_um, "%.2f"), ungated.backstop ? "backstop (alarm)" : "relay"}}});
    if (ir.gate)
      claims.note("Interrupted surface: " + std::to_string(ir.count) +
                  (ir.kind == Interruption::Kind::Flats ? " flat(s) " : " keyway(s) ") +
                  fmt(ir.depth_m * kUm) + " µm deep at " + fmt(ir.spindle_rpm) +
                  " rpm. Bridged (the last probe period replayed, guard " +
                  fmt(ir.guard_s * 1e3) + " ms; their mean delay " + fmt(bridge * 1e3, "%.2f") +
                  " ms is in (23)'s lag), the part finishes " + fmt(full_err_um_, "%.2f") +
                  " µm from target; read as size, " + fmt(ungated_um, "%.2f") + " µm.");
  }
}

// 3b. The cause of the full model's error: ripple, subharmonic motion, or both — the
// filters against the probe's regime (the seed's contact c_c = 5 N·s/m beside this one's).
void GaugingStudy::error_cause(io::RunOutput& out) const {
  Table cause{
      "What the full model's error (no noise) comes from: the filter against the probe's "
      "regime, each with its own calibrated (23)",
      {"filter", "contact damping c_c [N·s/m]", "probe spread at trip [µm]", "ripple at trip [mV]",
       "finished − target [µm]"},
      {}};
  json cause_json = json::array();
  using F = sensors::VibroContactGauge::Params::Filter;
  std::vector<sensors::VibroContactGauge::Params> variants;
  std::vector<double> contacts{5.0};  // the seed's example contact, and this one's
  if (d_.transducer.contact_damping_N_s_per_m != 5.0)
    contacts.push_back(d_.transducer.contact_damping_N_s_per_m);
  for (double cc : contacts)
    for (F f : {F::FirstOrder, F::SecondOrder, F::Synchronous}) {
      auto v = d_.transducer;
      v.contact_damping_N_s_per_m = cc;
      v.filter = f;
      variants.push_back(v);
    }
  std::vector<NoiselessPart> res(variants.size());
  core::parallel_for(variants.size(), [&](std::size_t i) {
    res[i] = noiseless_part(size_step_, variants[i], dt_, sc_.run.seed, sc_.run.duration_s);
  });
  for (std::size_t i = 0; i < variants.size(); ++i) {
    cause.rows.push_back({filter_name(variants[i].filter),
                          fmt(variants[i].contact_damping_N_s_per_m),
                          fmt(res[i].spread_m * kUm, "%.2f"), fmt(res[i].ripple_V * 1e3, "%.1f"),
                          fmt(res[i].error_m * kUm, "%.2f")});
    cause_json.push_back({{"filter", filter_name(variants[i].filter)},
                          {"contact_damping_N_s_per_m", variants[i].contact_damping_N_s_per_m},
                          {"probe_spread_um", json_number(res[i].spread_m * kUm)},
                          {"ripple_mV", json_number(res[i].ripple_V * 1e3)},
                          {"finished_error_um", json_number(res[i].error_m * kUm)}});
  }
  out.summary["error_cause"] = cause_json;
  out.report.tables.push_back(cause);
}

}  // namespace lathectl::systems::d_gauging::detail
