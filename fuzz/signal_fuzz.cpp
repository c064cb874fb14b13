// libFuzzer target for lathectl_vibsensor's recorded signals (io/signal_file.hpp): every input is
// read as a WAV (channel 0 and 1) and as a CSV; each must either throw InputError naming the file
// or give a positive finite rate and finite samples (at least 2).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/signal_file.hpp"

namespace {

template <class Parse>
void check(Parse&& parse, std::string_view file) {
  lathectl::io::Signal s;
  try {
    s = parse();
  } catch (const lathectl::io::InputError& e) {
    if (std::string_view(e.what()).find(file) == std::string_view::npos) std::abort();
    return;
  }
  if (!(s.rate_Hz > 0.0 && std::isfinite(s.rate_Hz)) || s.samples.size() < 2) std::abort();
  for (double v : s.samples)
    if (!std::isfinite(v)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lathectl;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  check([&] { return io::parse_wav(bytes, "fuzz.wav", 0); }, "fuzz.wav");
  check([&] { return io::parse_wav(bytes, "fuzz.wav", 1); }, "fuzz.wav");
  check([&] { return io::parse_signal_csv(bytes, "fuzz.csv"); }, "fuzz.csv");
  return 0;
}
