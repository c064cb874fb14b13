#include "lathectl/io/install_paths.hpp"

#include <cstdlib>
#include <system_error>

namespace lathectl::io {

namespace fs = std::filesystem;

namespace {

// exists() with the error_code overload: a directory the process may not enter (a 0700 home read
// by LinuxCNC's realtime user) is "absent", not an exception.
bool holds(const fs::path& dir, const std::string& probe) {
  std::error_code ec;
  if (probe.empty()) return fs::is_directory(dir, ec);
  return fs::exists(dir / probe, ec);
}

bool inside(const fs::path& file, const fs::path& dir) {
  std::error_code ec;
  const fs::path d = fs::weakly_canonical(dir, ec);
  if (ec || d.empty()) return false;
  const auto rel = file.lexically_relative(d);
  return !rel.empty() && *rel.begin() != "..";
}

fs::path g_program, g_prefix;  // set_program_location (set once, at a module's load)

}  // namespace

void set_program_location(const fs::path& file, const fs::path& prefix) {
  g_program = file;
  g_prefix = prefix;
}

fs::path self_executable() {
  if (!g_program.empty()) return g_program;
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : p;
}

std::string locate_tree(const char* env_var, const TreeLocations& tree, const std::string& probe) {
  if (const char* env = std::getenv(env_var); env && *env) return env;
  const fs::path exe = self_executable();
  if (!g_prefix.empty()) {
    const fs::path own = g_prefix / tree.installed_rel;
    if (holds(own, probe)) return own.string();
  } else if (!exe.empty() && exe.has_parent_path() && exe.parent_path().has_parent_path()) {
    const fs::path own = exe.parent_path().parent_path() / tree.installed_rel;
    if (holds(own, probe)) return own.string();
  }
  if (!exe.empty() && inside(exe, LATHECTL_BUILD_DIR) && holds(tree.source, probe))
    return tree.source;
  if (holds(tree.installed, probe)) return tree.installed;
  if (holds(tree.source, probe)) return tree.source;
  return tree.installed;
}

}  // namespace lathectl::io
