#pragma once
// What System E's section readers share across their files (settings.cpp reads the scenario,
// controller_settings.cpp its [controller] section). Not for hosts: they call read_settings().

#include <string>
#include <vector>

#include "systems/e_adaptive/settings.hpp"

namespace lathectl::io {
class TableReader;
}

namespace lathectl::systems::e_adaptive {

inline constexpr double kMs = 1e-3;  // a key in ms, read in s

extern const std::vector<std::string>
    kModes;  // the controllers' names, as the scenario spells them
[[nodiscard]] Mode mode_from(const std::string& s);
// A number as a user wrote it (shortest form, no trailing zeros).
[[nodiscard]] std::string fmt_number(double v);
// [controller] (required): the rig's controller parameters and what runs around them.
void read_controller(io::TableReader& root, RigConfig& e);

}  // namespace lathectl::systems::e_adaptive
