// The Python extension module lathectl._lathectl: the C++ behind the package `lathectl`
// (python/lathectl/__init__.py holds the Python side: Run, Lobes, the dict scenarios, the
// docstrings users read with help()). One binding file per group of names (bindings.hpp).
#include <dlfcn.h>
#include <pybind11/pybind11.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "bindings.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/install_paths.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl_version.hpp"

namespace fs = std::filesystem;

namespace lathectl::python {

namespace {

PyObject* g_input_error = nullptr;
std::thread::id g_main_thread;

// Thrown through the simulation by the poll once Python's SIGINT handler raised: not a
// std::exception, so that no `catch (const std::exception&)` on the way turns it into another.
struct Interrupted {};

// The module's own file: an installed module (<prefix>/lib/python3/dist-packages/lathectl/) finds
// its data under <prefix>/share/lathectl, a build tree's under the source tree.
void locate_self() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&locate_self), &info) == 0 || !info.dli_fname) return;
  std::error_code ec;
  const fs::path so = fs::weakly_canonical(info.dli_fname, ec);
  if (ec) return;
  fs::path prefix = so.parent_path();  // .../lathectl
  for (int up = 0; up < 4 && prefix.has_parent_path(); ++up) prefix = prefix.parent_path();
  const bool installed = so.parent_path().parent_path().filename() == "dist-packages" ||
                         so.parent_path().parent_path().filename() == "site-packages";
  io::set_program_location(so, installed ? prefix : fs::path());
}

}  // namespace

PyObject* input_error_type() { return g_input_error; }

py::object to_python(const nlohmann::json& j) {
  // Never destroyed: a static py::object would be released after the interpreter is gone.
  static auto* loads = new py::object(py::module_::import("json").attr("loads"));
  return (*loads)(j.dump());
}

void without_gil(const std::string& what, bool progress, const std::function<void()>& work) {
  std::optional<py::error_already_set> raised;
  bool interrupted = false;
  std::string input_error, runtime_error, os_error;
  {
    py::gil_scoped_release release;
    io::Progress line(what, progress ? io::Progress::Mode::Auto : io::Progress::Mode::Silent);
    line.set_poll([&] {
      if (std::this_thread::get_id() != g_main_thread) {
        if (interrupted) throw Interrupted{};
        return;
      }
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {
        raised.emplace();  // fetches the error the handler raised
        interrupted = true;
        throw Interrupted{};
      }
    });
    io::ProgressScope scope(line);
    try {
      work();
    } catch (const Interrupted&) {
      interrupted = true;
    } catch (const io::InputError& e) {
      input_error = e.what();
    } catch (const fs::filesystem_error& e) {
      os_error = e.path1().string() + ": " + e.code().message();
    } catch (const std::bad_alloc&) {
      runtime_error = "out of memory: the input asks for more than this machine has";
    } catch (const std::exception& e) {
      runtime_error = e.what();
    }
  }
  if (interrupted) {
    if (raised) throw std::move(*raised);
    throw py::error_already_set();
  }
  if (!input_error.empty()) {
    PyErr_SetString(g_input_error, input_error.c_str());
    throw py::error_already_set();
  }
  if (!os_error.empty()) {
    PyErr_SetString(PyExc_OSError, os_error.c_str());
    throw py::error_already_set();
  }
  if (!runtime_error.empty()) throw std::runtime_error(runtime_error);
}

}  // namespace lathectl::python

PYBIND11_MODULE(_lathectl, m) {
  using namespace lathectl::python;
  m.doc() = "lathectl's C++ core (use the package `lathectl`, which wraps it)";
  g_main_thread = std::this_thread::get_id();
  locate_self();
  g_input_error = PyErr_NewExceptionWithDoc(
      "lathectl.InputError",
      "Bad input (a scenario, a machine file, a calculator's inputs): the message is the one "
      "line `lathectl` prints, naming file, line and key (for a dict, the key's path).",
      PyExc_ValueError, nullptr);
  m.attr("InputError") = py::handle(g_input_error);
  m.attr("__version__") = LATHECTL_VERSION;
  m.attr("commit") = LATHECTL_GIT_COMMIT;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const lathectl::io::InputError& e) {
      PyErr_SetString(g_input_error, e.what());
    }
  });
  bind_run(m);
  bind_lobes(m);
  bind_design(m);
  bind_machines(m);
}
