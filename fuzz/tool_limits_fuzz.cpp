// libFuzzer target for lathectl_adaptive's per-tool limits table and teach-in file readers
// (hal/lathectl_tool_limits.hpp): any input either reads or fails with an InputError.
#include <cstdint>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl_tool_limits.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lathectl::hal::read_tool_table(text, "tools.toml");
  } catch (const lathectl::io::InputError&) {
  }
  try {
    (void)lathectl::hal::read_taught(text, "taught.toml");
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
