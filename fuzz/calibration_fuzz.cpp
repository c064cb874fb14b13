// libFuzzer target for a gauge's calibration CSV (io/calibration_reader.hpp) and its fit
// (design/gauge_calibration.hpp), as `lathectl design gauge --calibration` runs them: any input
// must throw InputError located in the file, or parse into points the fit either refuses
// (std::invalid_argument) or fits to finite numbers with A0 among the points and K > 0.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "lathectl/design/gauge_calibration.hpp"
#include "lathectl/io/calibration_reader.hpp"
#include "lathectl/io/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lathectl;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::vector<design::CalibrationPoint> points;
  try {
    points = io::parse_calibration_csv(bytes, "fuzz.csv");
  } catch (const io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.csv") == std::string_view::npos) std::abort();
    return 0;
  }
  try {
    const auto f = design::fit_calibration(points);
    if (!(f.gain_V_per_m > 0.0) || !std::isfinite(f.intercept_m) ||
        !std::isfinite(f.noise_sigma_V) || !(f.points_on_line >= 3) ||
        f.points_on_line > points.size() ||
        f.free_amplitude_m != points[f.points_on_line - 1].allowance_m)
      std::abort();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
