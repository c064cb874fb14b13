#pragma once
// What the machine objects' bindings share (machines.cpp, machine_adaptive.cpp,
// machine_modulation.cpp): a machine's inputs and outputs as tables of named fields, so that
// update(**inputs) sets the C++ Input by keyword without allocating, the outputs are one Python
// object reused from call to call (its attributes read the machine's Output when read), and the
// docstrings listing both with units are made from the same tables.
//
// Inputs keep their values between calls, as HAL pins do: update(force=1200.0) changes the force
// and leaves every other input as it was. A bad keyword or value raises before anything is set.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "lathectl/control/types.hpp"

namespace lathectl::python::machines {

// A Python number as a double, an integer, a bool; TypeError naming the input otherwise.
[[noreturn]] void bad_value(const char* cls, const char* name, PyObject* v, const char* expected);
inline double to_double(PyObject* v, const char* cls, const char* name) {
  if (PyFloat_CheckExact(v)) return PyFloat_AS_DOUBLE(v);
  const double x = PyFloat_AsDouble(v);
  if (x == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    bad_value(cls, name, v, "a number");
  }
  return x;
}
inline bool to_bool(PyObject* v, const char* cls, const char* name) {
  if (v == Py_True) return true;
  if (v == Py_False) return false;
  if (v == Py_None || PyUnicode_Check(v) || PyBytes_Check(v)) bad_value(cls, name, v, "a bool");
  const int r = PyObject_IsTrue(v);  // ints, floats, numpy's bools
  if (r < 0) throw py::error_already_set();
  return r != 0;
}
inline std::int32_t to_int(PyObject* v, const char* cls, const char* name) {
  const long x = PyLong_AsLong(v);
  if (x == -1 && PyErr_Occurred()) {
    PyErr_Clear();
    bad_value(cls, name, v, "an integer (32-bit)");
  }
  if (x < INT32_MIN || x > INT32_MAX) bad_value(cls, name, v, "an integer (32-bit)");
  return static_cast<std::int32_t>(x);
}

// One input: its keyword, how a Python value sets it and how it reads back, what it is (units).
template <class In>
struct InputField {
  const char* name;
  void (*set)(In&, PyObject*, const char* cls);
  py::object (*get)(const In&);
  const char* doc;
};
// One output: its attribute, how it reads, what it is (units).
template <class Out>
struct OutputField {
  const char* name;
  py::object (*get)(const Out&);
  const char* doc;
};

// Table rows: an input that is a member of In (a double, bool or int32 member; `expr` reads and
// writes it, e.g. `in.force`), an output read by `expr` from `o`.
#define LATHECTL_IN_F(In, key, expr, doc)                                         \
  InputField<In> {                                                                \
    key, [](In& in, PyObject* v, const char* c) { expr = to_double(v, c, key); }, \
        [](const In& in) -> py::object { return py::float_(expr); }, doc          \
  }
#define LATHECTL_IN_B(In, key, expr, doc)                                       \
  InputField<In> {                                                              \
    key, [](In& in, PyObject* v, const char* c) { expr = to_bool(v, c, key); }, \
        [](const In& in) -> py::object { return py::bool_(expr); }, doc         \
  }
#define LATHECTL_IN_I(In, key, expr, doc)                                      \
  InputField<In> {                                                             \
    key, [](In& in, PyObject* v, const char* c) { expr = to_int(v, c, key); }, \
        [](const In& in) -> py::object { return py::int_(expr); }, doc         \
  }
// An input whose member is not a plain bool or int (an enum): `set` assigns from `b` (a bool) or
// `i` (an int32), `get` reads it back as that.
#define LATHECTL_IN_BX(In, key, set_expr, get_expr, doc)                    \
  InputField<In> {                                                          \
    key,                                                                    \
        [](In& in, PyObject* v, const char* c) {                            \
          const bool b = to_bool(v, c, key);                                \
          set_expr;                                                         \
        },                                                                  \
        [](const In& in) -> py::object { return py::bool_(get_expr); }, doc \
  }
#define LATHECTL_IN_IX(In, key, set_expr, get_expr, doc)                   \
  InputField<In> {                                                         \
    key,                                                                   \
        [](In& in, PyObject* v, const char* c) {                           \
          const std::int32_t i = to_int(v, c, key);                        \
          set_expr;                                                        \
        },                                                                 \
        [](const In& in) -> py::object { return py::int_(get_expr); }, doc \
  }
#define LATHECTL_OUT_F(Out, key, expr, doc)                               \
  OutputField<Out> {                                                      \
    key, [](const Out& o) -> py::object { return py::float_(expr); }, doc \
  }
#define LATHECTL_OUT_B(Out, key, expr, doc)                              \
  OutputField<Out> {                                                     \
    key, [](const Out& o) -> py::object { return py::bool_(expr); }, doc \
  }
#define LATHECTL_OUT_I(Out, key, expr, doc)                                                     \
  OutputField<Out> {                                                                            \
    key, [](const Out& o) -> py::object { return py::int_(static_cast<long long>(expr)); }, doc \
  }

// The keywords of an input table as interned strings (a call's keywords are interned too, so a
// keyword is found by pointer; by text when not), and their docstring.
struct Keywords {
  std::vector<PyObject*> keys;  // never released: they live as long as the module
  std::string doc;
  [[nodiscard]] int find(PyObject* key) const noexcept;
};
template <class In>
Keywords keywords_of(std::span<const InputField<In>> fields) {
  Keywords k;
  for (const auto& f : fields) {
    k.keys.push_back(PyUnicode_InternFromString(f.name));
    k.doc += std::string("    ") + f.name + ": " + f.doc + "\n";
  }
  return k;
}

// Sets the inputs the keywords name (a vectorcall's: their names in `kwnames`, their values in
// `values`): all of them, or (an unknown keyword, a bad value) none.
template <class In>
void set_inputs(In& in, std::span<const InputField<In>> fields, const Keywords& k,
                PyObject* const* values, PyObject* kwnames, const char* cls) {
  if (kwnames == nullptr) return;
  In next = in;
  const Py_ssize_t n = PyTuple_GET_SIZE(kwnames);
  for (Py_ssize_t j = 0; j < n; ++j) {
    PyObject* key = PyTuple_GET_ITEM(kwnames, j);
    const int i = k.find(key);
    if (i < 0) {
      PyErr_Format(PyExc_TypeError, "%s: no input %R (help(lathectl.%s) lists them)", cls, key,
                   cls);
      throw py::error_already_set();
    }
    fields[static_cast<std::size_t>(i)].set(next, values[j], cls);
  }
  in = next;
}

// A method taking keyword inputs, called the fast way (METH_FASTCALL: no dict, no tuple made;
// pybind11's own dispatch made both and cost twice as much). Spec says what it is:
//   using State; using In; static const char* name (its "Class.method");
//   static std::span<const InputField<In>> fields(); static const Keywords& keywords();
//   static In& input(State&); static py::object run(State&)  (after the inputs are set).
template <class Spec>
PyObject* keyword_method(PyObject* self, PyObject* const* args, Py_ssize_t nargs,
                         PyObject* kwnames) noexcept {
  try {
    if (nargs != 0) {
      PyErr_Format(PyExc_TypeError, "%s takes keyword inputs only (name=value)", Spec::name);
      return nullptr;
    }
    // self is an instance of the class (the method descriptor checks it); its C++ object is
    // found directly (pybind11's one-base layout), not through a cast that looks its type up.
    auto vh = reinterpret_cast<py::detail::instance*>(self)->get_value_and_holder();
    if (!vh.holder_constructed()) {
      PyErr_Format(PyExc_TypeError, "%s: the machine was not made (its constructor raised)",
                   Spec::name);
      return nullptr;
    }
    auto& s = *vh.template value_ptr<typename Spec::State>();
    set_inputs<typename Spec::In>(Spec::input(s), Spec::fields(), Spec::keywords(), args, kwnames,
                                  Spec::name);
    return Spec::run(s).release().ptr();
  } catch (py::error_already_set& e) {
    e.restore();
  } catch (const py::cast_error&) {
    PyErr_Format(PyExc_TypeError, "%s: not a made machine", Spec::name);
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
  }
  return nullptr;
}

// Adds `Spec`'s method to a bound class as `method` with docstring `doc` (kept alive: static).
template <class Spec, class Class>
void def_keyword_method(Class& c, const char* method, const std::string& doc) {
  auto* def = new PyMethodDef{
      method, reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&keyword_method<Spec>)),
      METH_FASTCALL | METH_KEYWORDS, doc.c_str()};  // never freed
  PyObject* d = PyDescr_NewMethod(reinterpret_cast<PyTypeObject*>(c.ptr()), def);
  if (d == nullptr) throw py::error_already_set();
  py::setattr(c, method, py::reinterpret_steal<py::object>(d));
}

// The inputs as a dict (name: value), for inspection.
template <class In>
py::dict inputs_dict(const In& in, std::span<const InputField<In>> fields) {
  py::dict d;
  for (const auto& f : fields) d[f.name] = f.get(in);
  return d;
}

// The outputs' object: a view of the machine's Output (the machine kept alive by `owner`).
// One at a time per machine: update() returns the one alive (`*cache`), or makes one.
template <class State, class Out>
struct OutputView {
  std::shared_ptr<State> owner;
  const Out* out;
  PyObject** cache;
  OutputView(std::shared_ptr<State> s, const Out* o, PyObject** c)
      : owner(std::move(s)), out(o), cache(c) {}
  OutputView(const OutputView&) = delete;
  OutputView& operator=(const OutputView&) = delete;
  ~OutputView() { *cache = nullptr; }
};
template <class State, class Out>
py::object view_of(State& s, const Out* out, PyObject*& cache) {
  if (cache != nullptr) return py::reinterpret_borrow<py::object>(cache);
  py::object o = py::cast(new OutputView<State, Out>(s.shared_from_this(), out, &cache),
                          py::return_value_policy::take_ownership);
  cache = o.ptr();
  return o;
}

// Binds the outputs' class: an attribute per field, as_dict(), _fields, a repr listing them.
template <class State, class Out>
py::class_<OutputView<State, Out>> bind_outputs(py::module_& m, const char* name, const char* doc,
                                                std::span<const OutputField<Out>> fields) {
  using V = OutputView<State, Out>;
  py::class_<V> c(m, name, doc);
  py::list names;
  for (const auto& f : fields) {
    const auto get = f.get;
    c.def_property_readonly(
        f.name, [get](const V& v) { return get(*v.out); }, f.doc);
    names.append(f.name);
  }
  c.attr("_fields") = py::tuple(names);
  c.def(
      "as_dict",
      [fields](const V& v) {
        py::dict d;
        for (const auto& f : fields) d[f.name] = f.get(*v.out);
        return d;
      },
      "The outputs now as a dict (a copy: it does not change with the next update()).");
  c.def("__repr__", [fields, name](const V& v) {
    std::string s = std::string("<lathectl.") + name;
    for (const auto& f : fields) {
      const std::string r = py::repr(f.get(*v.out));
      s += " " + std::string(f.name) + "=" + r;
    }
    return s + ">";
  });
  return c;
}

// The reason codes (lathectl reasons): reason_name(code), and the whole table.
void bind_reasons(py::module_& m);

// Each system's machine class and its outputs' class (one file each besides machines.cpp).
void bind_adaptive(py::module_& m);    // machine_adaptive.cpp: E
void bind_modulation(py::module_& m);  // machine_modulation.cpp: B

}  // namespace lathectl::python::machines
