#pragma once
// System E's study (study.cpp: the runs, claims, summary and report; study_extra.cpp: the studies
// beside the runs), shared by the two files only.

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

namespace lathectl::systems::e_adaptive::detail {

using namespace io;
using nlohmann::json;

// A cycle time only when the part was finished; else where the run stopped (run.duration_s).
std::string cycle_cell(const Metrics& m);
std::string cycle_phrase(const Metrics& m);
// A controller as the controllers' table names it.
std::string short_name(Mode m);

struct Run {
  Rig rig;
  std::unique_ptr<MetricsAccumulator> acc;  // fed as the rig records
  std::unique_ptr<PathPlots> path;          // the compared plots, along the part
  std::unique_ptr<ChannelStream> csv;       // channels.csv / channels_compare.csv
  Metrics m;
  Mode mode = Mode::Fixed;
  std::string label;
};
// csv: the result file the run's channels go to (nullptr: none), streamed into `stage`.
void run_one(const Scenario& sc, RigConfig cfg, Mode mode, bool as_comparison, Run& r,
             const char* csv = nullptr, OutputStage* stage = nullptr);

// Cost per part (settings.hpp, Cost): machine time plus the share of an edge used.
struct PartCost {
  double machine = 0.0, tool = 0.0, total = 0.0;
};
PartCost part_cost(const Metrics& m, const Cost& c);
json metrics_json(const Run& r, const std::string& unit, const Cost& cost);

inline constexpr const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
Series constant(double x0, double x1, double y, const std::string& name);
std::string alarm_name(const sim::AlarmEvent& a);

// One planned depth t_p of the sweep: the tool-life verdicts (used / plan) of the seed law and
// of the depth-corrected law, at the part's hardness and at nominal hardness.
struct DepthVerdict {
  double depth_mm = 0.0, plan_min = 0.0;  // t_p, T(V_p, S_p, t_p)
  double seed = 0.0, seed_nominal = 0.0, corrected = 0.0, corrected_nominal = 0.0;
  double cycle_s = 0.0, edge_used = 0.0;  // the depth-corrected run's
};
json depth_json(const std::vector<DepthVerdict>& v);

// The scenario's controller and those compared with it on the same part; beside them the prior
// art given seed 004's tool-life budget and the tool-life verdict against the
// planned depth (item 5). The extra studies' tables and plot keep their places among the
// report's own (report() lays them out), where E's report has always shown them.
class EStudy final : public io::Study {
 public:
  explicit EStudy(const Scenario& sc)
      : Study(sc),
        st_(sc.get<Settings>()),
        power_(st_.rig.force_parameter == cutting::ForceParameter::Power),
        unit_(power_ ? "W" : "N"),
        pname_(power_ ? "cutting power"
                      : (st_.rig.force_parameter == cutting::ForceParameter::Pz ? "force Pz"
                                                                                : "force Py")) {}

 private:
  void run_controllers() override;
  void check_claims(Claims& claims) override;
  void extra_studies(RunOutput& out, Claims& claims) override;
  void summary(json& s) override;
  void report(Report& rep) override;
  void finish(RunOutput& out) override;

  void run_beside();
  void force_claims(const Run& r, Claims& claims) const;
  void productivity_claim(Claims& claims) const;
  void tool_life_claims(Claims& claims) const;
  void baseline_note(const Run& fixed, Claims& claims) const;
  void fault_claims(Claims& claims) const;
  void tradeoff_study(json& s, Claims& claims) const;
  void depth_study(json& s, Claims& claims);
  [[nodiscard]] std::vector<DepthVerdict> depth_verdicts() const;
  void depth_table_and_plot(const std::vector<DepthVerdict>& v);
  void depth_claims(const std::vector<DepthVerdict>& v, Claims& claims) const;
  void report_metrics(Report& rep) const;
  [[nodiscard]] Table controllers_table() const;
  [[nodiscard]] Table cost_table() const;
  void reasons_table(Report& rep) const;
  void run_plots(Report& rep) const;
  [[nodiscard]] const RigConfig& e() const { return st_.rig; }
  [[nodiscard]] const Run& main() const { return *runs_.front(); }
  [[nodiscard]] const std::vector<double>& depths() const { return st_.sweep_planned_depth_mm; }
  // The prior art at seed 004's tool budget: what its speed is raised to.
  [[nodiscard]] double budget_speed() const {
    return e().controller.speed_programmed_m_per_min * budget_speed_factor_;
  }

  const Settings& st_;
  const bool power_;
  const std::string unit_, pname_;          // the force parameter's unit and name
  std::vector<std::unique_ptr<Run>> runs_;  // the scenario's controller, then the compared
  std::array<const Run*, 3> by_mode_{};     // each controller's run (Mode's order), or null
  // Seed 004 and the prior art both finished, the prior art run again at the
  // speed that uses seed 004's share of an edge.
  bool tradeoff_ = false;
  Run budget_;
  double budget_speed_factor_ = std::nan("");
  // Item 5: the depth-corrected law at each planned depth; the seed law once (from the main run
  // when it is the seed law: it never reads t_p).
  bool main_seed_law_ = false;
  std::vector<std::unique_ptr<Run>> corrected_;
  Run seed_law_;
  Table depth_table_{
      "Tool-life verdict against the planned depth t_p (used / plan = ∫dt/T over "
      "time in cut / T(V_p, S_p, t_p))",
      {"t_p [mm]", "T plan [min]", "seed law used/plan", "seed law, nominal hardness",
       "depth-corrected used/plan", "depth-corrected, nominal hardness",
       "depth-corrected cycle [s]", "depth-corrected edge used"},
      {}};
  Plot depth_plot_{"Tool-life use against plan vs the planned depth",
                   "planned depth t_p [mm]",
                   "used / plan",
                   {},
                   {}};
};

}  // namespace lathectl::systems::e_adaptive::detail
