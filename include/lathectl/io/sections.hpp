#pragma once
// Scenario tables more than one system reads: [run], [material] and [tool], [[fault]], [spindle],
// the chatter model's [[mode]]s and a part's beam material (B's machine files, E's [chatter]).
// A system's own tables are read in its folder (systems/<x>/settings.cpp).

#include <cstdint>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/lobes.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "lathectl/sensors/faults.hpp"

namespace lathectl::io {

void read_run(TableReader& root, RunSettings& run);
// [material] (name from the library, force model) and [tool] (nose radius, approach angle and,
// with `wear`, [tool.wear]; with `orientation`, its key orientation, LinuxCNC's Q, whose default
// is the value it points at; with `angles`, its keys front_angle_deg and back_angle_deg into
// angles[0], angles[1], defaults the values there). `kienzle_only`: the system needs dF/db (system B).
void read_material_tool(TableReader& root, const MaterialLibrary& lib,
                        cutting::CuttingModel::Params& cutting,
                        cutting::DisturbanceParams* wear = nullptr, bool kienzle_only = false,
                        int* orientation = nullptr, double* angles = nullptr);
// [[fault]]: injected sensor faults.
std::vector<sensors::SensorFault> read_faults(TableReader& root);
// The spindle drive (systems B and E). With `defaults`, every key is optional and keeps the
// value already in `s`.
void read_spindle(TableReader& sp, drives::SpindleDrive::Params& s, bool defaults);
// [[mode]] (an array of tables under `root`): each a vibration mode of the chatter model
// (dynamics::Mode: k, ζ, f_n, direction to the chip thickness).
std::vector<dynamics::Mode> read_modes(TableReader& root);
// A slender part's beam material and damping (E, ρ, ζ, direction of its bending modes); with
// `defaults` E and ρ are optional and keep the values already in `b`.
void read_beam_material(TableReader& p, dynamics::BeamPart& b, bool defaults);

}  // namespace lathectl::io
