#pragma once
// A design calculator's inputs and outputs, each described once, in one table per calculator
// (design_<name>.cpp). The tables drive everything a user sees of them: the command-line flags
// and their --help lines, the range checks and their one-line errors, the JSON (the inputs; the
// results in SI and shop units), the text rows and the Markdown reference (`lathectl reference
// design`, generated into the docs).
//
// Why this shape: an input is the scenario reader's io::Param (key with its unit suffix, range,
// one line of meaning) plus the flag and a member pointer into the calculator's argument struct,
// whose initial values are the defaults; an output is a member pointer into a results struct with
// its SI and shop names. A calculator stays an ordinary function from arguments to results; the
// rows are data, so a new input or output is one row (and its line of formula) in one file.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "cli.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::cli {

// One input. param.key is its JSON key (the unit in its suffix: "d_mm"), param.range is checked
// in the shop unit, param.doc is the line of meaning. `field` is a plain double (its initial value
// is the default) or an optional (no default: the input is given or absent).
template <class Args>
struct Input {
  std::string_view flag;  // "--d-mm"
  io::Param param;
  std::string_view unit;  // shop unit for --help and the reference ("" for a pure number)
  std::variant<double Args::*, std::optional<double> Args::*> field;
  std::string_view note = {};  // what --help adds after the unit: "(instead of T)"
};

// One output: its text row label (and line of meaning), its SI and shop JSON keys and units, the
// shop/SI factor and where it is in the results struct. An empty key leaves it out of that JSON
// part; an optional that is empty is left out everywhere, a non-finite one is JSON null.
template <class R>
struct Output {
  std::string_view label;
  std::string_view si_key, si_unit;
  std::string_view shop_key, shop_unit;
  double shop_per_si = 1.0;
  std::variant<double R::*, bool R::*, std::optional<double> R::*> field;
};

// "> 0", ">= 0", "in (0, 1]", "" (any finite number): the bound in a range error and in --help.
std::string bound_text(const io::Range& r);
// The check of one flag's text: "VALUE: expected a finite number > 0".
CLI::Validator range_validator(const io::Range& r);
std::string format_number(double v);  // %g
// The header of the SI | shop table, and one row of it.
void print_header(const char* title);
void print_row(std::string_view label, double si, std::string_view si_unit, double shop,
               std::string_view shop_unit);
// A Markdown table (cells escaped for '|').
std::string markdown_table(const std::vector<std::string>& head,
                           const std::vector<std::vector<std::string>>& rows);

template <class A>
std::string help_line(const Input<A>& in) {
  std::string h(in.param.doc);
  if (!in.unit.empty()) h += " [" + std::string(in.unit) + "]";
  if (!in.note.empty()) h += " " + std::string(in.note);
  return h;
}

// Adds the inputs' flags to `sub`, bound to `args` (which must outlive the parse); the returned
// function stores the optional inputs given, to be called after parsing.
template <class A>
struct BoundInputs {
  std::vector<std::pair<CLI::Option*, std::optional<double> A::*>> optional;
  std::vector<std::pair<std::string_view, CLI::Option*>> options;
  std::unique_ptr<double[]> scratch;
  CLI::Option* option(std::string_view flag) const {
    for (const auto& [f, o] : options)
      if (f == flag) return o;
    return nullptr;
  }
  void apply(A& args) const {
    std::size_t k = 0;
    for (const auto& [opt, field] : optional) {
      if (opt->count() > 0) args.*field = scratch[k];
      ++k;
    }
  }
};

template <class A>
std::shared_ptr<BoundInputs<A>> add_inputs(CLI::App& sub, A& args,
                                           std::span<const Input<A>> inputs) {
  auto b = std::make_shared<BoundInputs<A>>();
  b->scratch = std::make_unique<double[]>(inputs.size());
  std::size_t k = 0;
  for (const auto& in : inputs) {
    CLI::Option* o = nullptr;
    if (const auto* f = std::get_if<double A::*>(&in.field)) {
      o = sub.add_option(std::string(in.flag), args.**f, help_line(in))->capture_default_str();
    } else {
      const auto of = std::get<std::optional<double> A::*>(in.field);
      o = sub.add_option(std::string(in.flag), b->scratch[k], help_line(in));
      b->optional.emplace_back(o, of);
      ++k;
    }
    o->check(range_validator(in.param.range));
    b->options.emplace_back(in.flag, o);
  }
  return b;
}

template <class A>
nlohmann::json inputs_json(const A& args, std::span<const Input<A>> inputs) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& in : inputs) {
    const std::string key(in.param.key);
    if (const auto* f = std::get_if<double A::*>(&in.field))
      j[key] = args.**f;
    else if (const auto& v = args.*std::get<std::optional<double> A::*>(in.field))
      j[key] = *v;
  }
  return j;
}

// The value of an output: nullopt when it is an empty optional; bools as 0/1 (is_bool says so).
template <class R>
std::optional<double> output_value(const R& r, const Output<R>& o) {
  if (const auto* f = std::get_if<double R::*>(&o.field)) return r.**f;
  if (const auto* f = std::get_if<bool R::*>(&o.field)) return (r.**f) ? 1.0 : 0.0;
  return r.*std::get<std::optional<double> R::*>(o.field);
}

template <class R>
void outputs_json(nlohmann::json& j, const R& r, std::span<const Output<R>> outputs,
                  const char* si = "si", const char* shop = "shop") {
  for (const auto& o : outputs) {
    const auto v = output_value(r, o);
    if (!v) continue;
    const bool is_bool = std::holds_alternative<bool R::*>(o.field);
    auto value = [&](double x) {
      if (is_bool) return nlohmann::json(x != 0.0);
      return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
    };
    if (!o.si_key.empty()) j[si][std::string(o.si_key)] = value(*v);
    if (!o.shop_key.empty()) j[shop][std::string(o.shop_key)] = value(*v * o.shop_per_si);
  }
}

template <class R>
void print_outputs(const R& r, std::span<const Output<R>> outputs) {
  for (const auto& o : outputs) {
    const auto v = output_value(r, o);
    if (!v) continue;
    if (std::holds_alternative<bool R::*>(o.field))
      std::printf("  %-34s %14s\n", std::string(o.label).c_str(), *v != 0.0 ? "yes" : "no");
    else
      print_row(o.label, *v, o.si_unit, *v * o.shop_per_si, o.shop_unit);
  }
}

// The last word on a result: every output present must be finite. The flags' ranges keep each
// input sensible, but a combination can still overflow ((Cv/V)^(1/m) with a small m); then the
// error names the output and `flags`, the inputs it comes from, rather than printing inf or nan.
template <class R>
void require_finite(const std::string& who, const R& r, std::span<const Output<R>> outputs,
                    std::string_view flags) {
  for (const auto& o : outputs) {
    const auto v = output_value(r, o);
    if (!v || std::isfinite(*v)) continue;
    throw io::InputError(who + "the " + std::string(o.label) + " comes out " +
                         (std::isnan(*v) ? "undefined (nan)" : "infinite") +
                         " for these inputs: " + std::string(flags) + " are too far apart");
  }
}

// The inputs as untyped rows (the reference's and the Python module's).
template <class A>
std::vector<CalculatorInput> input_rows(std::span<const Input<A>> inputs) {
  const A defaults{};
  std::vector<CalculatorInput> rows;
  for (const auto& in : inputs) {
    CalculatorInput r{std::string(in.flag), std::string(in.param.key), std::string(in.unit),
                      std::string(in.param.doc), bound_text(in.param.range), std::nullopt};
    if (!in.note.empty()) r.doc += " " + std::string(in.note);
    if (const auto* f = std::get_if<double A::*>(&in.field)) r.default_value = defaults.**f;
    rows.push_back(std::move(r));
  }
  return rows;
}

// The reference: the inputs (flag, JSON key, unit, range, default, meaning) and outputs.
template <class A>
std::string inputs_markdown(std::span<const Input<A>> inputs) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& r : input_rows<A>(inputs))
    rows.push_back({"`" + r.flag + "`", "`" + r.key + "`", r.unit,
                    r.range.empty() ? "any" : r.range,
                    r.default_value ? format_number(*r.default_value) : "—", r.doc});
  return markdown_table({"flag", "JSON key", "unit", "range", "default", "meaning"}, rows);
}

template <class R>
std::string outputs_markdown(std::span<const Output<R>> outputs, const char* si = "SI",
                             const char* shop = "shop") {
  std::vector<std::vector<std::string>> rows;
  auto cell = [](std::string_view key, std::string_view unit) {
    if (key.empty()) return std::string("—");
    return "`" + std::string(key) + "`" + (unit.empty() ? "" : " [" + std::string(unit) + "]");
  };
  for (const auto& o : outputs)
    rows.push_back(
        {std::string(o.label), cell(o.si_key, o.si_unit), cell(o.shop_key, o.shop_unit)});
  return markdown_table({"result", si, shop}, rows);
}

// What every calculator does with its result: with --json the inputs (and `more_inputs`: the
// flags that are not number rows but change the result) and the results in SI and shop units,
// else a title and one row per output.
template <class A, class R>
int print_result(const A& a, std::span<const Input<A>> inputs, const R& r,
                 std::span<const Output<R>> outputs, const char* title,
                 const nlohmann::json& more_inputs = nlohmann::json::object()) {
  if (a.json) {
    nlohmann::json j;
    j["inputs"] = inputs_json<A>(a, inputs);
    j["inputs"].update(more_inputs);
    outputs_json<R>(j, r, outputs);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  print_header(title);
  print_outputs<R>(r, outputs);
  return 0;
}

// A calculator's subcommand: its flags from the inputs, --json, the footer naming its docs page,
// and `compute` as the action. Returns the bound inputs (for rules between flags).
template <class A>
std::shared_ptr<BoundInputs<A>> add_calculator(CLI::App& sub, Commands& out,
                                               std::span<const Input<A>> inputs,
                                               const std::string& footer,
                                               int (*compute)(const A&)) {
  auto a = std::make_shared<A>();
  sub.footer(footer);
  auto bound = add_inputs<A>(sub, *a, inputs);
  sub.add_flag("--json", a->json, "print JSON (inputs, SI and shop units)");
  out.push_back({&sub, [a, bound, compute] {
                   bound->apply(*a);
                   return compute(*a);
                 }});
  return bound;
}

// The calculators that read a material (seed 004's): --material and --json besides the table's
// flags, and the shop-unit text rows. A has `std::string material` and `bool json`.
template <class A>
void add_material_calculator(CLI::App& sub, Commands& out, std::span<const Input<A>> inputs,
                             const std::string& footer, const std::string& material_help,
                             const std::string& json_help, int (*compute)(const A&)) {
  auto a = std::make_shared<A>();
  sub.footer(footer);
  auto bound = add_inputs<A>(sub, *a, inputs);
  sub.add_option("--material", a->material, material_help);
  sub.add_flag("--json", a->json, json_help);
  out.push_back({&sub, [a, bound, compute] {
                   bound->apply(*a);
                   return compute(*a);
                 }});
}
// A material with tool-life data from data/materials.toml (kept in `lib`), or an InputError
// starting with `who` that lists the known materials.
const cutting::Material& tool_life_material(io::MaterialLibrary& lib, const std::string& name,
                                            const std::string& who);
// One text row of a shop-unit result ("  label   value unit").
template <class R>
void print_shop_row(const R& r, const Output<R>& o) {
  if (const auto v = output_value(r, o))
    std::printf("  %-46s %14.6g %s\n", std::string(o.label).c_str(), *v,
                std::string(o.shop_unit).c_str());
}

// A calculator's section of the reference.
template <class A, class R>
std::string calculator_reference(std::span<const Input<A>> inputs,
                                 std::span<const Output<R>> outputs) {
  return "Inputs:\n\n" + inputs_markdown<A>(inputs) + "\nResults (`--json`: `si` and `shop`):\n\n" +
         outputs_markdown<R>(outputs);
}

}  // namespace lathectl::cli
