// libFuzzer target for the reader of LinuxCNC's canonical commands (io::parse_canon, what
// lathectl optimize reads from rs274): any input either reads or fails with an InputError.
#include <cstdint>
#include <string_view>

#include "lathectl/io/canon.hpp"
#include "lathectl/io/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lathectl::io::parse_canon(text, "canon.txt");
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
