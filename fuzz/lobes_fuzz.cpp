// libFuzzer target for the lobes machine-file parser (`lathectl lobes`): any input must either
// parse into a usable chatter system or throw InputError located in the file.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "lathectl/io/errors.hpp"
#include "systems/b_chatter/lobes.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto in = lathectl::b_chatter::parse_lobes_input(text, "fuzz.toml");
    if (in.system.modes.empty() || !(in.system.kf_N_per_m2 > 0.0) || !(in.max_rpm > in.min_rpm))
      std::abort();  // a parsed machine is complete
    for (const auto& m : in.system.modes)
      if (!(m.stiffness_N_per_m > 0.0) || !(m.natural_frequency_Hz > 0.0)) std::abort();
  } catch (const lathectl::io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.toml") == std::string_view::npos) std::abort();
  }
  return 0;
}
