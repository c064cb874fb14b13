// libFuzzer target for the reader of a LinuxCNC INI file (io::parse_linuxcnc_ini and
// io::lathe_machine, what lathectl optimize --ini reads): any input either reads or fails with
// an InputError.
#include <cstdint>
#include <string_view>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/linuxcnc_ini.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lathectl::io::lathe_machine(lathectl::io::parse_linuxcnc_ini(text, "machine.ini"));
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
