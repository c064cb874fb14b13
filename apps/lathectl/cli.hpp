#pragma once
// What the commands of lathectl share: how each adds itself to the program, where the docs are,
// and the exit codes. main.cpp parses the command line and runs the command chosen.
// Exit codes: 0 success, 1 internal failure, 2 bad input (one clear message), 3 `--strict` and a
// claim not met, an alarm raised or a part not finished.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace lathectl::cli {

constexpr int kBadInput = 2;
constexpr int kStrictFailure = 3;  // --strict: a claim not met, an alarm or an unfinished part

// A command: its (sub)command and what it does once the command line is parsed and chosen.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};
using Commands = std::vector<Command>;

// "docs/PAGE in the lathectl sources (installed: /usr/share/doc/lathectl/docs/PAGE)".
std::string doc(const std::string& page);

// One line for a command-line error CLI11 reports: the command it concerns, an unknown command
// named with the ones there are, a rejected value as "--flag VALUE: expected ... (what it is)".
std::string command_line_error(const CLI::App& app, const CLI::ParseError& e, int argc,
                               char** argv);

// The program: parses argv, runs the command chosen, prints its errors; returns the exit code.
int run_program(int argc, char** argv);

// The commands, one file each.
void add_run(CLI::App& app, Commands& out);
void add_check(CLI::App& app, Commands& out);
void add_demo(CLI::App& app, Commands& out);
void add_lobes(CLI::App& app, Commands& out);
void add_report(CLI::App& app, Commands& out);
void add_design(CLI::App& app, Commands& out);
void add_reference(CLI::App& app, Commands& out);
void add_compare(CLI::App& app, Commands& out);
void add_optimize(CLI::App& app, Commands& out);
void add_reasons(CLI::App& app, Commands& out);
void add_systems(CLI::App& app, Commands& out);
void add_sweep(CLI::App& app, Commands& out);

// One number input of a design calculator, its table row untyped (calculator.hpp, Input): what
// the Python module's lathectl.design.<name> needs to name its keyword arguments (the JSON keys)
// after the flags, and to document them.
struct CalculatorInput {
  std::string flag;   // "--d-mm"
  std::string key;    // "d_mm": the key of --json's "inputs"
  std::string unit;   // shop unit ("" for a pure number)
  std::string doc;    // the line of meaning, with the note ("(instead of T)") after it
  std::string range;  // "in [0.001, 1000]", "> 0", "" (any finite number)
  std::optional<double> default_value;  // none: given or absent
};

// The design calculators (design_<name>.cpp each; design.cpp lists them): the subcommand, the
// inputs and outputs as Markdown for `lathectl reference design`, the number inputs as rows.
struct Calculator {
  const char* name;         // "pulse-regulator"
  const char* description;  // the --help line and the reference's heading text
  void (*add)(CLI::App& sub, Commands& out);  // options and action of the subcommand `name`
  std::string (*reference)();
  std::vector<CalculatorInput> (*inputs)();
};
extern const Calculator kPulseRegulator, kAdaptiveSpeed, kPlannedMode, kGauge, kTracer,
    kModulation;
const std::vector<const Calculator*>& calculators();

}  // namespace lathectl::cli
