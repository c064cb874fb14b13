// lathectl.design.<name>: the design calculators. A call is the command line `lathectl design
// NAME ... --json` run by the program itself (cli::run_program: the same flags, checks, rules
// between flags and messages as the CLI), its JSON and its messages captured; the package
// (python/lathectl/design.py) names the keyword arguments after the calculators' input tables
// (cli::Calculator::inputs: JSON key ↔ flag) and puts the keys back into the messages.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "cli.hpp"

namespace lathectl::python {

namespace {

const cli::Calculator& calculator(const std::string& name) {
  for (const auto* c : cli::calculators())
    if (name == c->name) return *c;
  throw py::value_error("no design calculator '" + name + "'");
}

// The calculators: (command name, description).
py::list names() {
  py::list l;
  for (const auto* c : cli::calculators()) l.append(py::make_tuple(c->name, c->description));
  return l;
}

// A calculator's inputs: its table's number rows ("kind": "number"), then the subcommand's other
// options as CLI11 has them (--material, --filter: "text"; --force: "flag"), --json and --help left
// out: each a dict of flag, key, unit, doc, range, default.
py::list inputs(const std::string& name) {
  const auto& c = calculator(name);
  py::list l;
  std::vector<std::string> flags;
  for (const auto& r : c.inputs()) {
    py::dict d;
    d["kind"] = "number";
    d["flag"] = r.flag;
    d["key"] = r.key;
    d["unit"] = r.unit;
    d["doc"] = r.doc;
    d["range"] = r.range;
    d["default"] = r.default_value ? py::cast(*r.default_value) : py::none();
    l.append(d);
    flags.push_back(r.flag);
  }
  CLI::App app;
  cli::Commands commands;
  auto* sub = app.add_subcommand(c.name, c.description);
  c.add(*sub, commands);
  for (const CLI::Option* o : sub->get_options()) {
    const std::string flag = o->get_name();
    if (flag == "--help" || flag == "--json" ||
        std::find(flags.begin(), flags.end(), flag) != flags.end())
      continue;
    std::string key = flag.substr(flag.find_first_not_of('-'));
    for (auto& ch : key)
      if (ch == '-') ch = '_';
    py::dict d;
    d["kind"] = o->get_expected_max() == 0 ? "flag" : "text";
    d["flag"] = flag;
    d["key"] = key;
    d["unit"] = "";
    d["doc"] = o->get_description();
    d["range"] = "";
    d["default"] = o->get_default_str().empty() ? py::none() : py::cast(o->get_default_str());
    l.append(d);
  }
  return l;
}

// std::cout and std::cerr into strings while it lives.
class Capture {
 public:
  Capture() : out_(std::cout.rdbuf(o_.rdbuf())), err_(std::cerr.rdbuf(e_.rdbuf())) {}
  ~Capture() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  std::string out() const { return o_.str(); }
  std::string err() const { return e_.str(); }

 private:
  std::ostringstream o_, e_;
  std::streambuf *out_, *err_;
};

// `lathectl design NAME ARGS... --json`: (exit code, stdout, stderr). The GIL stays held: the
// program's streams are the process's, and no other Python thread must print into the capture.
py::tuple run(const std::string& name, const std::vector<std::string>& args) {
  (void)calculator(name);
  std::vector<std::string> words{"lathectl", "design", name};
  words.insert(words.end(), args.begin(), args.end());
  words.emplace_back("--json");
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  int rc = 0;
  std::string out, err;
  {
    Capture capture;
    rc = cli::run_program(static_cast<int>(words.size()), argv.data());
    out = capture.out();
    err = capture.err();
  }
  return py::make_tuple(rc, out, err);
}

}  // namespace

void bind_design(py::module_& m) {
  m.def("_design_names", &names);
  m.def("_design_inputs", &inputs, py::arg("name"));
  m.def(
      "_design_reference", [](const std::string& name) { return calculator(name).reference(); },
      py::arg("name"));
  m.def("_design_run", &run, py::arg("name"), py::arg("args"));
}

}  // namespace lathectl::python
