#pragma once
// A configuration a rig rejects because of how several settings combine (a step too coarse for
// a natural frequency, more recorded rows than memory allows, a component's own consistency
// check), naming the scenario key that decides it: "run.step_s", "controller", "cut.rpm". The
// scenario layer locates that key in the file (file:line:col); code that does not care still
// catches it as the std::invalid_argument it is. The host's type: the core names only its own
// parameters (core::ParameterError), and configure_as() maps them to scenario keys.

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::sim {

// A parameter error whose parameter is the scenario's: a key ("table.key") or a table
// ("controller") that decides the error.
class ConfigError : public core::ParameterError {
 public:
  using core::ParameterError::ParameterError;
  [[nodiscard]] const std::string& key() const noexcept { return parameter(); }
};

// Where a core model's own parameter comes from in the scenario: {"step", "run.step_s"}.
struct ParameterKey {
  std::string_view parameter;  // core::ParameterError::parameter()
  const char* key;             // the scenario key
};

// Runs a component's configure(); a std::invalid_argument it throws becomes a ConfigError at a
// scenario key. A ConfigError keeps its own, finer key; a core::ParameterError takes the key
// `keys` gives its parameter; anything else (or a parameter `keys` does not name) `key`, the
// scenario table that configures the component.
template <class F>
void configure_as(const char* key, std::initializer_list<ParameterKey> keys, F&& configure) {
  try {
    std::forward<F>(configure)();
  } catch (const ConfigError&) {
    throw;
  } catch (const core::ParameterError& e) {
    for (const ParameterKey& k : keys)
      if (k.parameter == e.parameter()) throw ConfigError(k.key, e.what());
    throw ConfigError(key, e.what());
  } catch (const std::invalid_argument& e) {
    throw ConfigError(key, e.what());
  }
}
template <class F>
void configure_as(const char* key, F&& configure) {
  configure_as(key, {}, std::forward<F>(configure));
}

}  // namespace lathectl::sim
