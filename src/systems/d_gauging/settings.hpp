#pragma once
// System D's settings (seed 003): the process (allowance, removal, disturbance, relay), the
// vibro-contact transducer, the threshold's kind and the Monte Carlo sizes. Every default is a
// member initialiser here or in the structs it holds; the section reader (settings.cpp) reads
// [process], [transducer], [gauge] and [monte_carlo] over them.

#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include "lathectl/design/vibro_gauge.hpp"
#include "lathectl/io/acceptance.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "systems/d_gauging/rig_config.hpp"

namespace lathectl::systems::d_gauging {

// [acceptance]: what the finished parts must achieve (settings.cpp describes each key).
extern const std::array<io::CriterionKey, 2> kAcceptanceKeys;

// [sequence]: the steps before size, as feeds relative to the size step's removal rate and the
// sizes above target where the next step starts (gauging_cycle makes their thresholds).
struct Sequence {
  bool enabled = false;  // the table is present
  double rough_factor = 4.0;
  double fine_factor = 2.0;
  double fine_m = 60e-6;
  double spark_m = 25e-6;
};

struct Settings : io::SettingsOf<Settings> {
  // The reader's disturbance is none unless [process] noise_sigma_um gives one.
  // The backstop is NaN until read: absent, it is target − tolerance (the lower tolerance limit).
  GaugingProcess process{.noise_variance_m2 = 0.0,
                         .backstop_m = std::numeric_limits<double>::quiet_NaN(),
                         .cycle = {},
                         .interruption = {}};
  sensors::VibroContactGauge::Params transducer;
  Sequence sequence;
  double tolerance_m = 10e-6;              // ± about the target
  std::string threshold = "calibrated";    // "seed" (23 with A0, K), "calibrated" (23 with the
                                           // full model's local line and the first-passage
                                           // bias), "calibrated_dynamic" or "given"
  double threshold_V = 0.0;                // when "given"
  bool force_threshold = false;            // run even when the threshold is outside the safe range
  std::size_t calibration_parts_max = 96;  // calibrated_dynamic: the most full-model parts
  std::size_t parts = 100000;              // linearised Monte Carlo
  std::size_t full_parts = 8;              // full-model Monte Carlo
  io::AcceptanceLimits acceptance{kAcceptanceKeys};  // [acceptance], or the defaults
};

// The relay's threshold and what bounds it, from the settings and the full model (settings.cpp):
// computed by the check (validate) and again by the run, the same way.
struct ThresholdPlan {
  design::GaugeLine seed_line;        // K, A0 of the closed forms
  design::GaugeLine calibrated_line;  // the full model's local line at the trip point
  design::GaugeLine line;             // the one the threshold uses
  double x_trip_m = 0.0;              // x_k + a·(T_f + t_r), where the relay should trip
  double threshold_V = 0.0;           // S_th
  design::SignalRange range;          // what the signal reaches, with its margin
  double largest_target_m = 0.0;      // where the safe range of targets ends
  [[nodiscard]] bool safe() const { return range.contains(threshold_V); }
};
ThresholdPlan plan_threshold(const Settings& d, double dt_s);

// The cycle's steps before size on `line`: fine where the size is target + fine_m (after rough
// at rough_factor·a), spark-out at target + spark_m (after fine at fine_factor·a), each (23) with
// `lag_s` (the filter's, the relay's and the bridges'); the rate factors of each command. No
// steps when the sequence is off. Throws std::invalid_argument when the spark-out threshold is
// not below `size_threshold_V` (what GaugeMachine would refuse).
GaugingCycle gauging_cycle(const Sequence& s, const design::GaugeLine& line,
                           const GaugingProcess& p, double lag_s, double size_threshold_V);

// The scenario's transducer on its step (run.step_s): what the model refuses is located at the
// scenario key of the parameter it names (run.step_s, transducer.magnet_gap_mm, ...; [transducer]
// for the rest) and thrown as io::InputError. The check (validate) and the run configure it so.
void configure_transducer(const io::Scenario& sc, sensors::VibroContactGauge& gauge);

// The section reader (settings.cpp): the settings from the file's tables.
std::unique_ptr<io::SystemSettings> read_settings(io::TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib);
// The section reader alone: what a component that only reads D's settings links (its
// lathectl_d_gauging_settings). The one place the system's letter is written.
inline constexpr io::Section kReadSection{"D", &read_settings, nullptr};
// The cross-checks that need the whole scenario (validate.cpp: the transducer's probe, the
// allowance against its free amplitude, the threshold against the signal's safe range).
void validate(const io::Scenario& sc);
// Reader and validation: the registry's entry.
inline constexpr io::Section kSection{kReadSection.system, &read_settings, &validate};

}  // namespace lathectl::systems::d_gauging
