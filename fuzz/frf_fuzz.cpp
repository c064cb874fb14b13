// libFuzzer target for measured FRF files (io/frf_reader.hpp: CSV, UFF 58 ASCII and 58b): any
// input must either throw InputError located in the file, or parse into an FRF the chatter model
// accepts (check_frf: ascending positive frequencies, finite values). A parsed FRF is then
// smoothed and fitted as `lathectl lobes` does; the fit may refuse an FRF with no peak
// (std::invalid_argument), but must not crash, hang or return a non-finite mode.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "lathectl/dynamics/frf.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/frf_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lathectl;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  dynamics::Frf frf;
  try {
    frf = io::parse_frf(bytes, "fuzz.frf");
  } catch (const io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.frf") == std::string_view::npos) std::abort();
    return 0;
  }
  dynamics::check_frf(frf);  // throws (a finding) if the reader let a bad FRF through
  if (frf.frequency_Hz.size() > 4000) return 0;  // the fit's cost, not its correctness
  try {
    const auto fit = dynamics::fit_modes(frf, 3);
    for (const auto& m : fit.modes)
      if (!std::isfinite(m.natural_frequency_Hz) || !std::isfinite(m.stiffness_N_per_m) ||
          !std::isfinite(m.damping_ratio))
        std::abort();
    (void)dynamics::smooth_frf(frf, dynamics::smoothing_half_window_Hz(fit),
                               dynamics::kSmoothingOrder);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
