#pragma once
// What system D's registry entry (src/systems/registry.cpp) points at besides its study's run.

#include <filesystem>
#include <string>

#include "lathectl/io/estimate.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::d_gauging {

// Its study's cost before it runs (estimate.cpp).
io::RunEstimate estimate(const io::Scenario& sc);

// `lathectl report PATH` of scripts/linuxcnc-sim-gauge's series (summary.json with the parts,
// parts.csv, no operation log): as `lathectl run`'s for system D, the size table, Cp/Cpk and the
// histogram of finished sizes against the tolerance (session_report.cpp). Whether PATH (a
// directory, or a file in it) is such a session:
bool is_session(const std::filesystem::path& path);
// Its report.html (out empty: beside it); the exit code.
int session_report(const std::filesystem::path& path, const std::string& out);

}  // namespace lathectl::systems::d_gauging
