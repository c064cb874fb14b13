#pragma once
// A model's configure() refusing one of its own parameters, named as the model names it
// ("tool2_lag_mm", "step", "magnet_gap_m"): the core knows no scenario file nor HAL pin. Whoever
// configured the model maps the name to where the value came from (a rig: sim::configure_as and
// the scenario key, "run.step_s"); code that does not care catches the std::invalid_argument it is.

#include <stdexcept>
#include <string>
#include <utility>

namespace lathectl::core {

class ParameterError : public std::invalid_argument {
 public:
  ParameterError(std::string parameter, const std::string& message)
      : std::invalid_argument(message), parameter_(std::move(parameter)) {}
  [[nodiscard]] const std::string& parameter() const noexcept { return parameter_; }

 private:
  std::string parameter_;
};

}  // namespace lathectl::core
