#pragma once
// What system E's registry entry (src/systems/registry.cpp) points at besides its study's run.

#include <filesystem>
#include <string>

#include "lathectl/io/estimate.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::systems::e_adaptive {

// Its study's cost before it runs (estimate.cpp).
io::RunEstimate estimate(const io::Scenario& sc);

// `lathectl report PATH` of the operation log lathectl_oplog writes on LinuxCNC (operations.json,
// one row per program line with feed moves, or the directory holding it): the per-line table, the
// taught references, the operator messages, and, when scripts/linuxcnc-sim's recording lies beside
// it (signals.csv), load against limit and the adaptive feed over time (session_report.cpp).
// Whether PATH (a directory, or a file in it) is such a session:
bool is_session(const std::filesystem::path& path);
// Its report.html (out empty: beside it); the exit code.
int session_report(const std::filesystem::path& path, const std::string& out);

}  // namespace lathectl::systems::e_adaptive
