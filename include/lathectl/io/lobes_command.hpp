#pragma once
// `lathectl lobes MACHINE.toml --out DIR`: stability lobes of a machine's chatter model, by the
// frequency domain and, independently, by semi-discretization; writes lobes.json, lobes.csv and
// lobes.html. The machine file:
//   [cutting] kf_N_per_mm2                       cutting-force coefficient along the chip thickness
//   [[mode]]  stiffness_N_per_m, damping_ratio, natural_frequency_Hz, angle_deg
//   [speed]   min_rpm, max_rpm
//   [lobes]   (optional) max_lobes, sd_speeds (semi-discretization check points)

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::io {

struct LobesInput {
  dynamics::ChatterSystem system;
  double min_rpm = 1000.0, max_rpm = 10000.0;
  int max_lobes = 40;
  int sd_speeds = 40;
};

LobesInput load_lobes_input(const std::string& path);  // throws InputError
// Computes and writes the outputs; returns lobes.json's content.
nlohmann::json run_lobes(const LobesInput& in, const std::filesystem::path& out_dir);

}  // namespace lathectl::io
