#pragma once
// System B's study (study.cpp: the runs, claims and summary; study_report.cpp: the report), shared
// by the two files only.

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <thread>

#include "lathectl/core/parallel.hpp"
#include "lathectl/dynamics/van_der_pol.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/b_chatter/metrics.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl::systems::b_chatter::detail {

using io::Claims;
using io::Compare;
using io::fmt;
using io::json_number;
using io::Plot;
using io::Series;
using io::Table;
using nlohmann::json;

// The rig records streamed (its memory bounded whatever the cut's length): the measures are taken
// row by row, csv (nullptr: none) is written into `stage` as the rows come. Without csv the run is
// only measured (the sweep): no plots are kept either.
void run_one(const io::Scenario& sc, const RigConfig& cfg, Run& r, io::OutputStage* stage,
             const char* csv = nullptr);
std::string source_name(control::ModulationSource s);

const char* const kColors[] = {"#d62728", "#1f77b4"};

// One feed of the sweep: with and without modulation.
struct SweepPoint {
  double feed = 0.0;
  Run on, off;
};

// The quenching condition under both readings of the seed's 1.41, for the a0 the module planned on
// (just above the dead zone, chatter still growing) and for the document's a0, the steady
// amplitude without modulation. K = a0·m_d·|ω_d² − ω_m²|: the module's required force
// is c·K (multiply) or K/c (divide).
struct Quenching {
  double k_planned = kNaN, k_steady = kNaN, a0_steady_um = kNaN, a0_planned_um = kNaN;
};

// The cut as programmed and, to compare, the same without modulation; the linear limits that
// explain where modulation can help; the van der Pol check; the sweep over the feed.
class ChatterStudy final : public io::Study {
 public:
  explicit ChatterStudy(const io::Scenario& sc)
      : Study(sc),
        st_(sc.get<Settings>()),
        b_(st_.rig),
        twin_(b_.setup != TwinSetup::Single),
        modulated_(b_.source != control::ModulationSource::None),
        compared_(modulated_ && st_.compare),
        turret_(static_cast<int>(b_.turret)),
        s_prog_(b_.feed_mm_per_rev * b_.rpm),
        dead_zone_um_(b_.vibration.dead_zone_m * 1e6) {}

 private:
  void run_controllers() override;
  void check_claims(Claims& claims) override;
  void extra_studies(io::RunOutput& out, Claims& claims) override;
  void summary(json& s) override;
  void report(io::Report& rep) override;
  void finish(io::RunOutput& out) override;

  void find_linear_limits();
  [[nodiscard]] Quenching quenching() const;
  void quenching_claims(Claims& claims) const;
  void setup_notes(Claims& claims) const;
  [[nodiscard]] json run_metrics() const;
  [[nodiscard]] json surface_metrics() const;
  void model_metrics(json& m) const;
  void report_metrics(io::Report& rep) const;
  void time_plots(io::Report& rep) const;
  [[nodiscard]] Plot stability_plot() const;
  [[nodiscard]] const Run& main() const { return *with_; }
  [[nodiscard]] const control::ModulatedFeedController::Output& mo() const {
    return main().rig.module_output();
  }
  [[nodiscard]] bool automatic_engaged() const {
    return b_.source == control::ModulationSource::Automatic && mo().engaged;
  }

  const Settings& st_;
  const RigConfig& b_;
  const bool twin_, modulated_, compared_;
  const int turret_;     // the modulated turret's index
  const double s_prog_;  // mm/min per turret
  const double dead_zone_um_;
  std::unique_ptr<Run> with_ = std::make_unique<Run>(), without_ = std::make_unique<Run>();
  const Run* off_ = nullptr;  // the run without modulation, if any
  Limits lim_;                // at the softest position of the cut, lim_x_
  double lim_x_ = 0.0;
  double vdp_B_ = 0.0;  // van der Pol: the measured quenching threshold (a0 = 2)
  Quenching quench_;
  std::vector<std::unique_ptr<SweepPoint>> sweep_;
};

}  // namespace lathectl::systems::b_chatter::detail
