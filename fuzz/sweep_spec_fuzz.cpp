// libFuzzer target for lathectl sweep's spec reader (sweep::parse_spec): any input is read or
// refused with io::InputError; a spec read has well-formed varied keys (parse_key_path) and the
// places of its keys.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "lathectl/io/errors.hpp"
#include "sweep/spec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto spec = lathectl::sweep::parse_spec(text, "fuzz.toml");
    for (const auto& key : spec.varied_keys()) {
      if (lathectl::sweep::parse_key_path(key).size() < 2) std::abort();  // refused by the reader
      if (spec.place_of(key).line <= 0) std::abort();
    }
    if (spec.grid.empty() && spec.random.empty()) std::abort();
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
