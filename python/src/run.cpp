// lathectl.run and lathectl.check: a scenario (a file, or the text the package made of a dict)
// read by the same reader as `lathectl run`, run by the same registry, its output kept whole
// (summary, full-precision channels, report) so that Run.write gives the files `lathectl run`
// writes.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/install_paths.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/study.hpp"
#include "systems/estimate.hpp"
#include "systems/registry.hpp"

namespace lathectl::python {

namespace {

// A finished run: what `lathectl run` would write, held in memory.
struct RunResult {
  io::RunOutput out;
  std::string name, system;
};

const io::MaterialLibrary& materials() {
  static const io::MaterialLibrary lib = io::MaterialLibrary::load_default();
  return lib;
}

}  // namespace

// `text` given: the scenario's text (a dict made into TOML by the package), `label` its name in
// messages and the directory its relative files are found in; else `label` is the file.
io::Scenario read_scenario(const std::optional<std::string>& text, const std::string& label) {
  const std::string t = text ? *text : io::read_scenario_text(label);
  return systems::parse_scenario(t, label, materials());
}

namespace {

py::list warnings_of(const io::Scenario& sc) {
  py::list w;
  for (const auto& s : sc.warnings) w.append(s);
  return w;
}

py::tuple check(const std::optional<std::string>& text, const std::string& label) {
  std::optional<io::Scenario> sc;
  without_gil("check", false, [&] { sc.emplace(read_scenario(text, label)); });
  const auto e = systems::estimate(*sc);
  return py::make_tuple(warnings_of(*sc), sc->system, sc->name, systems::summary_text(e));
}

// report false: summary.json alone (io::SummaryOnly, a sweep's case), no report built.
py::tuple run(const std::optional<std::string>& text, const std::string& label,
              std::optional<std::uint64_t> seed, bool progress, bool report) {
  auto r = std::make_shared<RunResult>();
  std::optional<io::Scenario> sc;
  without_gil("run", false, [&] { sc.emplace(read_scenario(text, label)); });
  if (seed) sc->run.seed = *seed;
  r->name = sc->name;
  r->system = sc->system;
  without_gil("run " + sc->name, progress, [&] {
    io::ChannelStream::KeepValues keep;
    std::optional<io::SummaryOnly> summary_only;
    if (!report) summary_only.emplace();
    r->out = systems::run_scenario(*sc);
  });
  return py::make_tuple(r, warnings_of(*sc));
}

// The columns as one C-contiguous array per channel (copies: a column of the row-major rows is
// strided, and a user's array should not keep the whole table alive).
py::dict channels(const RunResult& r) {
  const auto& v = r.out.channels_values;
  py::dict d;
  const std::size_t w = v.names.size();
  const std::size_t n = w ? v.rows.size() / w : 0;
  for (std::size_t c = 0; c < w; ++c) {
    py::array_t<double> a(static_cast<py::ssize_t>(n));
    double* p = a.mutable_data();
    for (std::size_t i = 0; i < n; ++i) p[i] = v.rows[i * w + c];
    d[py::str(v.names[c])] = std::move(a);
  }
  return d;
}

void write(const RunResult& r, const std::string& dir) {
  without_gil("write", false, [&] {
    io::prepare_output_dir(dir, "dir");
    io::write_outputs(r.out, std::filesystem::path(dir));
  });
}

}  // namespace

void bind_run(py::module_& m) {
  py::class_<RunResult, std::shared_ptr<RunResult>>(m, "_RunResult")
      .def_property_readonly("summary_json", [](const RunResult& r) { return r.out.summary.dump(2); })
      .def_property_readonly("summary", [](const RunResult& r) { return to_python(r.out.summary); })
      .def_property_readonly("ok", [](const RunResult& r) { return r.out.verdict.ok(); })
      .def_property_readonly("verdict", [](const RunResult& r) { return r.out.verdict.line(); })
      .def_property_readonly("headline", [](const RunResult& r) { return r.out.headline; })
      .def_property_readonly("name", [](const RunResult& r) { return r.name; })
      .def_property_readonly("system", [](const RunResult& r) { return r.system; })
      .def("channels", &channels)
      .def("write", &write, py::arg("dir"));
  m.def("_check", &check, py::arg("text"), py::arg("label"));
  m.def("_run", &run, py::arg("text"), py::arg("label"), py::arg("seed"), py::arg("progress"),
        py::arg("report") = true);
  m.def("_data_dir", [] { return io::data_dir(); });
  m.def("_examples_dir", [] {
    return io::locate_tree("LATHECTL_EXAMPLES_DIR",
                           {LATHECTL_EXAMPLES_DIR, LATHECTL_EXAMPLES_SUBDIR,
                            LATHECTL_INSTALLED_EXAMPLES_DIR},
                           "");
  });
}

}  // namespace lathectl::python
