#pragma once
// Scenario tables more than one system reads: [run], [material] and [tool], [[fault]], [spindle].
// A system's own tables are read in its folder (systems/<x>/settings.cpp).

#include <cstdint>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "lathectl/sim/faults.hpp"

namespace lathectl::io {

void read_run(TableReader& root, RunSettings& run);
// [material] (name from the library, force model) and [tool] (nose radius, approach angle and,
// with `wear`, [tool.wear]). `kienzle_only`: the system needs dF/db (system B).
void read_material_tool(TableReader& root, const MaterialLibrary& lib,
                        cutting::CuttingModel::Params& cutting,
                        cutting::DisturbanceParams* wear = nullptr, bool kienzle_only = false);
// [[fault]]: injected sensor faults.
std::vector<sim::SensorFault> read_faults(TableReader& root);
// The spindle drive (systems B and E). With `defaults`, every key is optional and keeps the
// value already in `s`.
void read_spindle(TableReader& sp, drives::SpindleDrive::Params& s, bool defaults);

}  // namespace lathectl::io
