#pragma once
// What `lathectl lobes` computed (lobes.cpp), and its outputs written from it
// (lobes_outputs.cpp): lobes.json, lobes.csv, lobes.html. The Python module's lathectl.lobes
// computes the same and keeps it in memory (compute_lobes, lobes_json, lobe_curves).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "lathectl/dynamics/lobes.hpp"
#include "systems/b_chatter/lobes.hpp"

namespace lathectl::systems::b_chatter {

// The critical depth along the part, frequency domain at each position.
struct AlongPart {
  double x_m, critical_m, chatter_Hz, lowest_in_range_m, f1_Hz, k_static;
};

// What run_lobes computes; lobes.json, lobes.csv and lobes.html are written from it.
struct LobesRun {
  dynamics::FrequencyDomainResult fd;
  // Semi-discretization by bisection at sd_speed, and the frequency domain at the same speeds.
  std::vector<double> sd_speed, sd_depth, fd_depth;
  double worst = 0.0;  // their largest relative difference
  std::optional<dynamics::SdChart> chart;
  double chart_worst = 0.0;
  int chart_compared = 0;
  std::vector<AlongPart> along;
  std::vector<Pocket> pockets;
};

// What run_lobes computes, nothing written. progress: optional.
LobesRun compute_lobes(const LobesInput& in, io::Progress* progress = nullptr);

// lobes.json's content.
nlohmann::json lobes_json(const LobesInput& in, const LobesRun& r);

// The curves of lobes.csv (and of lobes.html's diagram), depths in mm, NaN where no lobe bounds
// the depth (an empty cell in lobes.csv): the frequency-domain envelope at 1001 speeds over the
// range, the semi-discretization limits by bisection (empty without sd_speeds), the SD chart's
// boundary (empty without a chart).
struct LobeCurve {
  std::vector<double> speed_rpm, depth_mm;
};
struct LobeCurves {
  LobeCurve envelope, sd, chart;
};
LobeCurves lobe_curves(const LobesInput& in, const LobesRun& r);

// lobes.csv, lobes.html and lobes.json (j), as one output set in out_dir.
void write_lobes_outputs(const LobesInput& in, const LobesRun& r, const nlohmann::json& j,
                         const std::filesystem::path& out_dir);

}  // namespace lathectl::systems::b_chatter
