// libFuzzer target for the scenario parser: any input must either parse into a complete
// Scenario or throw InputError with a located message. Anything else (a crash, a sanitizer
// report, another exception type) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/registry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto lib =
      lathectl::io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto sc = lathectl::systems::parse_scenario(text, "fuzz.toml", lib);
    if (sc.name.empty()) std::abort();  // a parsed scenario is complete
  } catch (const lathectl::io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.toml") == std::string_view::npos) std::abort();
  }
  return 0;
}
