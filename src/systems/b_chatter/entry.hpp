#pragma once
// What system B's registry entry (src/systems/registry.cpp) points at besides its study's run.

#include <filesystem>
#include <string>

#include "lathectl/io/estimate.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::b_chatter {

// Its study's cost before it runs (estimate.cpp).
io::RunEstimate estimate(const io::Scenario& sc);

// `lathectl report PATH` of scripts/linuxcnc-sim-twin's session on the twin-turret lathe
// (summary.json, signals.csv and report.txt, no operation log): its metrics and the vibration, the
// turrets' feeds and the flagged axis's offset over time (session_report.cpp). Whether PATH (a
// directory, or a file in it) is such a session:
bool is_session(const std::filesystem::path& path);
// Its report.html (out empty: beside it); the exit code.
int session_report(const std::filesystem::path& path, const std::string& out);

}  // namespace lathectl::systems::b_chatter
