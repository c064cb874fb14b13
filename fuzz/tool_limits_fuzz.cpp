// libFuzzer target for lathectl_adaptive's per-tool limits table and teach-in file readers
// (src/systems/e_adaptive/tool_limits.hpp): any input either reads or fails with an InputError.
#include <cstdint>
#include <string>

#include "lathectl/io/errors.hpp"
#include "systems/e_adaptive/tool_limits.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lathectl::systems::e_adaptive::read_tool_table(text, "tools.toml");
  } catch (const lathectl::io::InputError&) {
  }
  try {
    (void)lathectl::systems::e_adaptive::read_taught(text, "taught.toml");
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
