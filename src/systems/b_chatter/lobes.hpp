#pragma once
// `lathectl lobes MACHINE.toml --out DIR`: stability lobes of a machine's chatter model (system
// B's), by the frequency domain and, independently, by semi-discretization (limit depths at
// sd_speeds speeds by bisection, and a speed × depth chart of the SD map's unstable roots);
// writes lobes.json, lobes.csv and lobes.html. The machine file — [cutting], [[mode]] and/or [part] (a slender part
// between centres, dynamics/beam.hpp), [speed], optional [lobes] — is read in lobes_input.cpp,
// where each key is described once (describe_machine_file; docs/machine-file-reference.md).

#include <cstddef>
#include <filesystem>
#include <memory>
#include <nlohmann/json_fwd.hpp>  // run_lobes returns one: its callers include json.hpp
#include <optional>
#include <string>
#include <vector>

#include "lathectl/dynamics/lobes.hpp"
#include "systems/b_chatter/lobes_input.hpp"

namespace lathectl::io {
class Progress;
}  // namespace lathectl::io

namespace lathectl::systems::b_chatter {

// One stable pocket of the lobes, as a machinist would run it: the depth at the pocket's top
// divided by the safety factor (and cut to the power and torque limits), the spindle speed in
// the middle of the speeds where that depth is stable (lobes_recommend.cpp),
// the metal-removal rate Q = π·D·n·h·b, and how far the speed may drift either way before the
// envelope falls to that depth (the nearest lobe, in rpm).
struct Pocket {
  double pocket_top_rpm = 0.0, pocket_top_depth_m = 0.0;  // the envelope's local maximum
  double speed_rpm = 0.0;       // recommended: the middle of the stable interval at depth_m
  double limit_depth_m = 0.0;   // the envelope at speed_rpm; +inf where no lobe reaches
  double depth_m = 0.0;         // recommended
  std::string limited_by;       // "chatter", "power", "torque"
  double mrr_m3_per_s = 0.0;
  double power_W = 0.0, torque_Nm = 0.0;  // at depth_m
  double margin_below_rpm = 0.0, margin_above_rpm = 0.0;
  bool below_reaches_range_end = false, above_reaches_range_end = false;  // no lobe that side
};
// The `in.recommend.pockets` best pockets of the envelope in the speed range: those with a margin
// of at least 1 % of their speed each way first, then by removal rate, then by margin.
std::vector<Pocket> recommend_pockets(const dynamics::FrequencyDomainResult& fd,
                                      const LobesInput& in);

// Computes and writes the outputs; returns lobes.json's content, with "warnings" (speeds where
// no lobe reaches, lobes whose minimum lies outside the speed range). progress: optional.
nlohmann::json run_lobes(const LobesInput& in, const std::filesystem::path& out_dir,
                         io::Progress* progress = nullptr);

}  // namespace lathectl::systems::b_chatter
