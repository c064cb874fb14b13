// System E's studies beside the runs (io::Study::extra_studies): the prior art at seed 004's tool
// budget and the planned-depth sweep.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>

#include "lathectl/control/types.hpp"
#include "lathectl/core/parallel.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/e_adaptive/metrics.hpp"
#include "systems/e_adaptive/plots.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/e_adaptive/study_phases.hpp"

namespace lathectl::systems::e_adaptive::detail {

void EStudy::extra_studies(RunOutput& out, Claims& claims) {
  if (tradeoff_) tradeoff_study(out.summary, claims);
  if (!depths().empty()) depth_study(out.summary, claims);
}

// Seed 004 against the prior art at equal tool use: cost per part, the edge price at which the
// two cost the same, the prior art's cycle time interpolated to seed 004's tool use.
void EStudy::tradeoff_study(json& s, Claims& claims) const {
  const Run& seed = *by_mode_[2];
  const Run& prior = *by_mode_[1];
  const Cost& cost = st_.cost;
  const std::string law = e().life_law ? "the tool-life law" : "seed 004";
  const PartCost cs = part_cost(seed.m, cost), cp = part_cost(prior.m, cost);
  claims.check("cost per part (machine time + edge used), " + law + " / prior art (< 1; " +
                   fmt(cs.total, "%.3f") + " against " + fmt(cp.total, "%.3f") + ")",
               cs.total / cp.total, Compare::Below, 1.0);
  // The tool price at which the two would cost the same per part.
  const double du = seed.m.tool_life_used_fraction - prior.m.tool_life_used_fraction;
  const double dm = (prior.m.cycle_time_s - seed.m.cycle_time_s) / 3600.0 * cost.machine_rate_per_h;
  const double breakeven =
      du > 0.0 ? dm / du - cost.tool_change_min / 60.0 * cost.machine_rate_per_h : std::nan("");
  const double u0 = prior.m.tool_life_used_fraction, c0 = prior.m.cycle_time_s;
  const double u1 = budget_.m.tool_life_used_fraction, c1 = budget_.m.cycle_time_s;
  const double u = seed.m.tool_life_used_fraction;
  const double c_equal =
      budget_.m.finished && std::abs(std::log(u1 / u0)) > 1e-9
          ? c0 * std::exp(std::log(c1 / c0) * std::log(u / u0) / std::log(u1 / u0))
          : std::nan("");
  s["tool_use_tradeoff"] = {{"seed_to_prior_tool_use", json_number(u / u0)},
                            {"seed_to_prior_cycle_time", json_number(seed.m.cycle_time_s / c0)},
                            {"breakeven_tool_edge_cost", json_number(breakeven)},
                            {"prior_art_equal_budget",
                             {{"speed_m_per_min", json_number(budget_speed())},
                              {"cycle_time_s", json_number(c1)},
                              {"tool_life_used_fraction", json_number(u1)},
                              {"cycle_time_at_seed_tool_use_s", json_number(c_equal)}}}};
  claims.check("equal tool use: prior art given " + law +
                   "'s tool-life budget (speed raised to " + fmt(budget_speed(), "%.1f") +
                   " m/min, cycle " + fmt(c_equal, "%.1f") + " s interpolated to " + (e().life_law ? "its" : "the seed's") + " use); cycle time " +
                   law + " / prior art (< 1)",
               seed.m.cycle_time_s / c_equal, Compare::Below, 1.0);
  claims.note(law + " uses " + fmt(u / u0, "%.3f") + "× the prior art's tool life for " +
              fmt(seed.m.cycle_time_s / c0, "%.3f") +
              "× its cycle time; at these rates the two cost the same per part when an edge "
              "costs " +
              fmt(breakeven, "%.1f") + " (the [cost] default: " + fmt(cost.tool_edge_cost) + ")");
}

// The tool-life verdict (used / plan) of the seed law and the depth-corrected law at each
// planned depth t_p, at the part's hardness and at nominal hardness.
void EStudy::depth_study(json& s, Claims& claims) {
  const std::vector<DepthVerdict> v = depth_verdicts();
  s["planned_depth_sweep"] = depth_json(v);
  depth_table_and_plot(v);
  depth_claims(v, claims);
}

std::vector<DepthVerdict> EStudy::depth_verdicts() const {
  const Run& sl = main_seed_law_ ? main() : seed_law_;
  cutting::CuttingModel cut;
  cut.configure(e().cutting);
  std::vector<DepthVerdict> v;
  for (std::size_t k = 0; k < depths().size(); ++k) {
    const double d = depths()[k];
    const double plan = cut.tool_life_min(e().controller.speed_programmed_m_per_min,
                                          e().controller.feed_planned_mm_per_rev, d);
    const Run& rc = *corrected_[k];
    v.push_back({.depth_mm = d,
                 .plan_min = plan,
                 .seed = sl.m.tool_life_used_fraction * plan * 60.0 / sl.m.time_in_cut_s,
                 .seed_nominal = sl.m.tool_life_used_nominal_hardness_fraction * plan * 60.0 /
                                 sl.m.time_in_cut_s,
                 .corrected = rc.m.tool_life_used_fraction / rc.m.tool_life_plan_fraction,
                 .corrected_nominal =
                     rc.m.tool_life_used_nominal_hardness_fraction / rc.m.tool_life_plan_fraction,
                 .cycle_s = rc.m.cycle_time_s,
                 .edge_used = rc.m.tool_life_used_fraction});
  }
  return v;
}

json depth_json(const std::vector<DepthVerdict>& v) {
  json jd = json::array(), js = json::array(), jc = json::array(), jcyc = json::array(),
       jplan = json::array(), jsn = json::array(), jcn = json::array();
  for (const DepthVerdict& p : v) {
    jsn.push_back(json_number(p.seed_nominal));
    jcn.push_back(json_number(p.corrected_nominal));
    jd.push_back(p.depth_mm);
    jplan.push_back(json_number(p.plan_min));
    js.push_back(json_number(p.seed));
    jc.push_back(json_number(p.corrected));
    jcyc.push_back(json_number(p.cycle_s));
  }
  return {{"planned_depth_mm", jd},
          {"tool_life_planned_min", jplan},
          {"seed_law_used_to_plan", js},
          {"seed_law_used_to_plan_nominal_hardness", jsn},
          {"depth_corrected_used_to_plan", jc},
          {"depth_corrected_used_to_plan_nominal_hardness", jcn},
          {"depth_corrected_cycle_time_s", jcyc}};
}

void EStudy::depth_table_and_plot(const std::vector<DepthVerdict>& v) {
  Series ss{"seed law V_p·(S_p/S)^y_v", {}, {}, kColors[0], false, true};
  Series sd{"depth-corrected law ·(t_p/t̂)^x_v", {}, {}, kColors[2], false, true};
  Series ssn{"seed law, at nominal hardness", {}, {}, kColors[0], true, true};
  Series sdn{"depth-corrected law, at nominal hardness", {}, {}, kColors[2], true, true};
  for (const DepthVerdict& p : v) {
    for (Series* series : {&ss, &sd, &ssn, &sdn}) series->x.push_back(p.depth_mm);
    ss.y.push_back(p.seed);
    sd.y.push_back(p.corrected);
    ssn.y.push_back(p.seed_nominal);
    sdn.y.push_back(p.corrected_nominal);
    depth_table_.rows.push_back({fmt(p.depth_mm), fmt(p.plan_min, "%.1f"), fmt(p.seed, "%.3f"),
                                 fmt(p.seed_nominal, "%.3f"), fmt(p.corrected, "%.3f"),
                                 fmt(p.corrected_nominal, "%.3f"), fmt(p.cycle_s, "%.1f"),
                                 fmt(p.edge_used, "%.4f")});
  }
  depth_plot_.series = {ss, sd, ssn, sdn, constant(depths().front(), depths().back(), 1.0, "plan")};
}

void EStudy::depth_claims(const std::vector<DepthVerdict>& v, Claims& claims) const {
  double worst = 0.0, corrected_max = v.front().corrected;
  for (const DepthVerdict& p : v) {
    worst = std::max(worst, std::abs(p.corrected_nominal - 1.0));
    corrected_max = std::max(corrected_max, p.corrected);
  }
  claims.note(
      "the seed law's used/plan scales as t_p^(−x_v/m): its verdict is the choice of "
      "t_p, from " +
      fmt(v.front().seed, "%.2f") + " at t_p = " + fmt(depths().front()) + " mm to " +
      fmt(v.back().seed, "%.2f") + " at " + fmt(depths().back()) + " mm");
  claims.check(
      "depth-corrected law, what it is designed to hold (tool life at nominal "
      "hardness): largest |used/plan − 1| over the planned depths (≤ 0.15)",
      worst, Compare::AtMost, 0.15);
  claims.note(
      "with the part's hardness (1.0–1.3 along it here) in the tool-life law, the "
      "depth-corrected law uses " +
      fmt(v.front().corrected, "%.2f") + "–" + fmt(corrected_max, "%.2f") +
      "× the plan at every t_p: hardness, which no force-only law can tell from depth, "
      "not the planned depth, then sets the verdict");
}

}  // namespace lathectl::systems::e_adaptive::detail
