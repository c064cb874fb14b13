#pragma once
// A configuration a rig rejects because of how several settings combine (a step too coarse for
// a natural frequency, more recorded rows than memory allows, a component's own consistency
// check), naming the scenario key that decides it: "run.step_s", "controller", "cut.rpm". The
// scenario layer locates that key in the file (file:line:col); code that does not care still
// catches it as the std::invalid_argument it is.

#include <stdexcept>
#include <string>
#include <utility>

namespace lathectl::sim {

class ConfigError : public std::invalid_argument {
 public:
  ConfigError(std::string key, const std::string& message)
      : std::invalid_argument(message), key_(std::move(key)) {}
  // A scenario key ("table.key") or a table ("controller") that decides the error.
  [[nodiscard]] const std::string& key() const noexcept { return key_; }

 private:
  std::string key_;
};

// Runs a component's configure(); a std::invalid_argument it throws is attributed to `key` (the
// scenario table that configures the component). A ConfigError keeps its own, finer key.
template <class F>
void configure_as(const char* key, F&& configure) {
  try {
    std::forward<F>(configure)();
  } catch (const ConfigError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw ConfigError(key, e.what());
  }
}

}  // namespace lathectl::sim
