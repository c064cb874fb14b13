#pragma once
// `lathectl design gauge --calibration FILE.csv` (design_gauge_calibration.cpp): the gauge from a
// measured calibration, called by design_gauge.cpp's compute with the process flags.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "lathectl/design/vibro_gauge.hpp"

namespace lathectl::cli {

struct CalibrationRun {
  std::string path;               // --calibration
  design::GaugeInput in;          // its process, filter and relay fields (the transducer's unused)
  std::optional<double> tolerance_um;
  bool json = false, force = false;
  nlohmann::json inputs;          // --json's "inputs": the flags that apply, given back as they are
};
int gauge_from_calibration(const CalibrationRun& run);
// The reference's table of what --calibration gives.
std::string calibration_outputs_markdown();

}  // namespace lathectl::cli
