// The local engine, and the hand-over to the Dask driver.
#include "sweep/engine.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <regex>

#include "lathectl/core/parallel.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/install_paths.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl/io/study.hpp"
#include "systems/registry.hpp"

extern char** environ;

namespace lathectl::sweep {
namespace {

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

Result run_case(const Case& c, const io::MaterialLibrary& lib) {
  const auto t0 = std::chrono::steady_clock::now();
  Result r{c.id, "ok", "", 0.0, std::nullopt};
  const io::SummaryOnly summary_only;  // the case keeps summary.json alone: no report built
  try {
    const auto sc = systems::parse_scenario(c.scenario, case_label(c.base_dir, c.id), lib);
    r.summary = systems::run_scenario(sc).summary.dump(2);
  } catch (const std::exception& e) {
    r.status = "error";
    r.message = one_line(e.what());
  }
  r.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::size_t run_local(const std::vector<Case>& cases, Store& store, unsigned workers,
                      const io::MaterialLibrary& lib) {
  const auto done = store.done();
  std::vector<const Case*> todo;
  for (const auto& c : cases)
    if (!done.contains(c.id)) todo.push_back(&c);
  if (todo.empty()) return 0;
  io::Progress progress("sweep");
  std::atomic<std::size_t> finished{0}, errors{0};
  core::parallel_for(
      todo.size(),
      [&](std::size_t i) {
        const Result r = run_case(*todo[i], lib);
        if (r.status != "ok") ++errors;
        store.record(r);
        const std::size_t n = ++finished;
        progress.update(static_cast<double>(n) / static_cast<double>(todo.size()),
                        std::to_string(n) + " of " + std::to_string(todo.size()) + " cases" +
                            (errors ? ", " + std::to_string(errors.load()) + " failed" : ""));
      },
      workers);
  progress.finish();
  return todo.size();
}

std::string find_dask_driver(const std::string& scheduler) {
  if (!std::regex_match(scheduler, std::regex(R"(tcp://[^\s:/]+:[0-9]{1,5})")))
    throw io::InputError("--scheduler " + scheduler +
                         ": expected a Dask scheduler's address, tcp://HOST:PORT");
  const std::string pydir = io::locate_tree(
      "LATHECTL_PYTHON_DIR",
      {LATHECTL_BUILD_PYTHON_DIR, "lib/python3/dist-packages", LATHECTL_INSTALLED_PYTHON_DIR},
      "lathectl/sweep_dask.py");
  if (!std::filesystem::exists(std::filesystem::path(pydir) / "lathectl" / "sweep_dask.py"))
    throw io::InputError("--scheduler: the Dask driver lathectl.sweep_dask is not in " + pydir +
                         " (install the python3-lathectl package, or build the Python module)");
  return pydir;
}

void run_dask(const std::string& pydir, const std::string& scheduler,
              const std::filesystem::path& dir) {
  const char* old = std::getenv("PYTHONPATH");
  const std::string pp = pydir + (old && *old ? ":" + std::string(old) : "");
  setenv("PYTHONPATH", pp.c_str(), 1);
  std::string dir_s = dir.string(), sched = scheduler;
  std::vector<char*> argv = {const_cast<char*>("/usr/bin/python3"), const_cast<char*>("-m"),
                             const_cast<char*>("lathectl.sweep_dask"),
                             const_cast<char*>("--scheduler"), sched.data(), dir_s.data(),
                             nullptr};
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
    throw std::runtime_error("cannot start /usr/bin/python3 for the Dask driver");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("the Dask driver (python3 -m lathectl.sweep_dask) failed (" +
                             (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                                : std::string("killed by a signal")) +
                             "); rerun the same command to run the cases not yet done");
}

}  // namespace lathectl::sweep
