// lathectl.lobes, lathectl.read_frf, lathectl.fit_modes: a machine file (a path, or the text the
// package made of a dict) read by the same reader as `lathectl lobes`, its lobes computed by the
// same code (systems::b_chatter::compute_lobes) and kept in memory: lobes.json's content and the
// curves lobes.csv holds, at full precision. The measured FRFs by the [[frf]] tables' readers
// (io/frf_reader) and their modal fit (dynamics::fit_modes), as the machine file's path uses them.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <complex>
#include <cstring>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "lathectl/dynamics/frf.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/frf_reader.hpp"
#include "lathectl/io/progress.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "systems/b_chatter/lobes_outputs.hpp"

namespace lathectl::python {

namespace {

namespace b = systems::b_chatter;

py::array_t<double> array(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
  return a;
}

py::dict curve(const b::LobeCurve& c) {
  py::dict d;
  d["speed_rpm"] = array(c.speed_rpm);
  d["depth_mm"] = array(c.depth_mm);
  return d;
}

// `text` given: the machine file's text (a dict made into TOML by the package), `label` its name
// in messages and the directory its relative files ([[frf]] file) are found in; else `label` is
// the file. Returns (lobes.json as a dict, {"envelope"|"sd"|"chart": {speed_rpm, depth_mm}}).
py::tuple lobes(const std::optional<std::string>& text, const std::string& label, bool progress) {
  std::optional<b::LobesInput> in;
  without_gil("lobes", false, [&] {
    in.emplace(text ? b::parse_lobes_input(*text, label) : b::load_lobes_input(label));
  });
  nlohmann::json j;
  b::LobeCurves c;
  without_gil("lobes", progress, [&] {
    const b::LobesRun r = b::compute_lobes(*in, io::ProgressScope::current());
    j = b::lobes_json(*in, r);
    c = b::lobe_curves(*in, r);
  });
  py::dict curves;
  curves["envelope"] = curve(c.envelope);
  curves["sd"] = curve(c.sd);
  curves["chart"] = curve(c.chart);
  return py::make_tuple(to_python(j), curves);
}

py::tuple read_frf(const std::string& path) {
  dynamics::Frf f;
  without_gil("read_frf", false, [&] { f = io::read_frf_file(path); });
  py::array_t<std::complex<double>> h(static_cast<py::ssize_t>(f.receptance_m_per_N.size()));
  auto* p = h.mutable_data();
  for (std::size_t k = 0; k < f.receptance_m_per_N.size(); ++k) p[k] = f.receptance_m_per_N[k];
  return py::make_tuple(array(f.frequency_Hz), h);
}

// The modes as the machine file's [[mode]] tables (angle 0: the fit is of the FRF as given,
// already along the chip thickness), with the fit's relative residual.
py::tuple fit_modes(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& f_Hz,
    const py::array_t<std::complex<double>, py::array::c_style | py::array::forcecast>& h,
    int max_modes) {
  if (f_Hz.ndim() != 1 || h.ndim() != 1)
    throw py::value_error("fit_modes: frequency_Hz and H must be 1-D arrays");
  if (f_Hz.size() != h.size())
    throw py::value_error("fit_modes: frequency_Hz has " + std::to_string(f_Hz.size()) +
                          " values, H " + std::to_string(h.size()) + ": one H per frequency");
  if (max_modes < 1) throw py::value_error("fit_modes: max_modes must be at least 1");
  dynamics::Frf frf;
  frf.frequency_Hz.assign(f_Hz.data(), f_Hz.data() + f_Hz.size());
  frf.receptance_m_per_N.assign(h.data(), h.data() + h.size());
  dynamics::FrfFit fit;
  without_gil("fit_modes", false, [&] {
    try {
      fit = dynamics::fit_modes(frf, max_modes);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(std::string("fit_modes: ") + e.what());
    }
  });
  py::list modes;
  for (const auto& m : fit.modes) {
    py::dict d;
    d["stiffness_N_per_m"] = m.stiffness_N_per_m;
    d["damping_ratio"] = m.damping_ratio;
    d["natural_frequency_Hz"] = m.natural_frequency_Hz;
    d["angle_deg"] = m.angle_rad * 180.0 / std::numbers::pi;
    modes.append(d);
  }
  return py::make_tuple(modes, fit.residual);
}

}  // namespace

void bind_lobes(py::module_& m) {
  m.def("_lobes", &lobes, py::arg("text"), py::arg("label"), py::arg("progress"));
  m.def("_read_frf", &read_frf, py::arg("path"));
  m.def("_fit_modes", &fit_modes, py::arg("frequency_Hz"), py::arg("H"), py::arg("max_modes"));
}

}  // namespace lathectl::python
