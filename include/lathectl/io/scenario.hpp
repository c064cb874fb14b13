#pragma once
// Scenario files (TOML): a system, a machine, a material, a part and its disturbances, a
// controller and its settings, run length and step. Shop units in key names; converted to SI
// here. Unknown keys, missing keys, wrong types and out-of-range values are InputErrors naming
// file, line and key. Nothing runs on a half-read scenario: parsing builds the whole Scenario
// or throws.

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {

struct RunSettings {
  double duration_s = 10.0;
  double step_s = 1e-4;
  double record_interval_s = 2e-3;
  std::uint64_t seed = 1;
};

// A system's own settings (its folder's settings.hpp), held by the Scenario. Derive from
// SettingsOf<YourSettings>; the scenario copies them with the rest.
struct SystemSettings {
  virtual ~SystemSettings() = default;
  [[nodiscard]] virtual std::unique_ptr<SystemSettings> clone() const = 0;
};
template <class Derived>
struct SettingsOf : SystemSettings {
  [[nodiscard]] std::unique_ptr<SystemSettings> clone() const override {
    return std::make_unique<Derived>(static_cast<const Derived&>(*this));
  }
};
// An owning, copyable slot (a copy clones).
class SettingsSlot {
 public:
  SettingsSlot() = default;
  SettingsSlot(const SettingsSlot& o) : p_(o.p_ ? o.p_->clone() : nullptr) {}
  SettingsSlot& operator=(const SettingsSlot& o) {
    if (this != &o) p_ = o.p_ ? o.p_->clone() : nullptr;
    return *this;
  }
  SettingsSlot(SettingsSlot&&) noexcept = default;
  SettingsSlot& operator=(SettingsSlot&&) noexcept = default;
  ~SettingsSlot() = default;
  void reset(std::unique_ptr<SystemSettings> p) { p_ = std::move(p); }
  [[nodiscard]] SystemSettings* get() const { return p_.get(); }

 private:
  std::unique_ptr<SystemSettings> p_;
};

struct Scenario {
  std::string file;    // where it came from (for messages and the summary)
  std::shared_ptr<const KeyLocations> keys;  // where the file wrote each key (for messages)
  std::string system;  // "A" … "E" (systems/registry.cpp)
  std::string name;
  std::string description;
  bool demonstrates_failure = false;  // a failure on purpose (lathectl demo lists it apart)
  RunSettings run;
  std::shared_ptr<const ParamLog> params;  // every key read, with its value (the report's table)
  // Values read but not ones a shop would mean ("file:line:col: key 'k': ..."): printed on
  // stderr by load_scenario ("warning: ..."), listed in the report and summary.json.
  std::vector<std::string> warnings;
  SettingsSlot settings;                   // the system's own (get<T>())

  // The system's settings as its type; a logic_error if the scenario is another system's.
  template <class T>
  [[nodiscard]] const T& get() const {
    return const_cast<Scenario*>(this)->get<T>();
  }
  template <class T>
  [[nodiscard]] T& get() {
    auto* p = dynamic_cast<T*>(settings.get());
    if (!p) throw std::logic_error(file + ": the scenario holds another system's settings");
    return *p;
  }
};

// How one system reads its part of a scenario file. The common part (system, name, description,
// [run]) is read first; `read` reads the system's tables from `root` and returns its settings
// (it may also fill the Scenario's common fields); every key left unread is then an error; last,
// `validate` (optional) makes the cross-checks that need the whole scenario, typically by
// configuring the system's rig once (throw_at_key turns its rejection into the user's error).
struct Section {
  std::string_view system;  // "E"
  std::unique_ptr<SystemSettings> (*read)(TableReader& root, Scenario& sc,
                                          const MaterialLibrary& lib) = nullptr;
  void (*validate)(const Scenario& sc) = nullptr;
};

// A scenario of any system: systems::parse_scenario and systems::load_scenario
// (src/systems/registry.hpp, which knows them all).
// A scenario of one system only (what a HAL component links: its own section reader, no other).
Scenario parse_scenario(std::string_view text, const std::string& file_label,
                        const MaterialLibrary& materials, const Section& section);
Scenario load_scenario(const std::string& path, const MaterialLibrary& materials,
                       const Section& section);
// The general form: the file's `system` must be one of `sections`.
Scenario parse_scenario(std::string_view text, const std::string& file_label,
                        const MaterialLibrary& materials, const std::vector<const Section*>& sections);
// The text of a scenario file (InputError when it is a directory or cannot be read).
std::string read_scenario_text(const std::string& path);
// The reference of a system's keys: its section reader run in describe mode (common part first).
// `variant` 1: required keys get other in-range values (TableReader::describing).
ParamLog describe_section(const Section& section, const MaterialLibrary& materials,
                          int variant = 0);
// Prints the scenario's warnings on stderr, "warning: " and one a line (load_scenario does).
void print_warnings(const Scenario& sc);

// A rig's (or a model's) rejection of a parsed scenario, as the InputError a user reads: a
// sim::ConfigError at the key it names, any other std::invalid_argument at `fallback_key` (a
// table whose settings it checks) or, without one, at the file.
[[noreturn]] void throw_at_key(const Scenario& sc, const std::invalid_argument& e,
                               const std::string& fallback_key = "");


}  // namespace lathectl::io
