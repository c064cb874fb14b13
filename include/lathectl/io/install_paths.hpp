#pragma once
// Where the running program finds the project's file trees (data/, the examples): the program's
// own location decides, so an installed binary uses its installed files even when the source tree
// it was built from is still on the machine, and a build-tree binary uses the source tree.

#include <filesystem>
#include <string>

namespace lathectl::io {

// One file tree in its two homes.
struct TreeLocations {
  std::string source;         // in the source tree (absolute)
  std::string installed_rel;  // relative to an install prefix, e.g. "share/lathectl"
  std::string installed;      // under the configured install prefix (absolute)
};

// The executable of this process (/proc/self/exe resolved), or empty when unknown; in a library
// loaded by another program (the Python module, whose process is python3) the file given to
// set_program_location instead.
[[nodiscard]] std::filesystem::path self_executable();
// For a library that carries lathectl into another program: `file` is the library itself and
// `prefix` its install prefix (/usr for /usr/lib/python3/dist-packages/lathectl/_lathectl.so),
// used by locate_tree in place of the executable's.
void set_program_location(const std::filesystem::path& file, const std::filesystem::path& prefix);

// The directory of `tree` for the running program, `probe` a file that must exist in it ("" to
// require only the directory), in this order:
//  1. $env_var when set and non-empty;
//  2. <prefix>/installed_rel when the executable is <prefix>/<dir>/<name> (an installed program,
//     e.g. /usr/bin/lathectl or LinuxCNC's /usr/bin/rtapi_app: its own prefix's files);
//  3. the source tree when the executable lies in this project's build tree;
//  4. the configured install location when it holds the probe;
//  5. the source tree when it holds the probe (a build's HAL modules copied into LinuxCNC);
//  6. the configured install location (the error that follows names it).
// Never throws on unreadable directories (they count as absent).
[[nodiscard]] std::string locate_tree(const char* env_var, const TreeLocations& tree,
                                      const std::string& probe);

}  // namespace lathectl::io
