#pragma once
// What `lathectl lobes` computed (lobes.cpp), and its outputs written from it
// (lobes_outputs.cpp): lobes.json, lobes.csv, lobes.html.

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

// lobes.json's content.
nlohmann::json lobes_json(const LobesInput& in, const LobesRun& r);
// lobes.csv, lobes.html and lobes.json (j), as one output set in out_dir.
void write_lobes_outputs(const LobesInput& in, const LobesRun& r, const nlohmann::json& j,
                         const std::filesystem::path& out_dir);

}  // namespace lathectl::systems::b_chatter
