#pragma once
// Sensor 4's force parameter (system E): which quantity of the cut it reads — the tangential
// force Pz or the radial force Py from a dynamometer, or the cutting power Nc = Pz·V (the
// spindle's power meter minus its idle power) — and that quantity's value for given forces. One
// switch for every place that needs it (the rig, its worst-case feed, the LinuxCNC plant).

#include "lathectl/cutting/cutting_model.hpp"

namespace lathectl::cutting {

enum class ForceParameter { Pz, Py, Power };

// The parameter's value [N, or W for Power] given the forces and the cutting power [W].
[[nodiscard]] constexpr double force_parameter(ForceParameter which, const Forces& f,
                                               double cut_power_W) noexcept {
  switch (which) {
    case ForceParameter::Pz:
      return f.Pz;
    case ForceParameter::Py:
      return f.Py;
    case ForceParameter::Power:
      return cut_power_W;
  }
  return f.Pz;
}

}  // namespace lathectl::cutting
