// libFuzzer target for lathectl sweep's spec reader (sweep::parse_spec): any input is read or
// refused with io::InputError; a spec read has well-formed varied keys (parse_key_path) and the
// places of its keys, and a [report] whose keys are two of the heat maps' axes.
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
    if (const auto& o = spec.lobes) {  // [report]: two distinct grid keys of the heat maps' axes
      const auto axis = [&](const std::string& key) {
        return (spec.grid.size() > 0 && spec.grid[0].key == key) ||
               (spec.grid.size() > 1 && spec.grid[1].key == key);
      };
      if (!axis(o->speed) || !axis(o->depth) || o->speed == o->depth) std::abort();
      if (!(o->depth_exponent >= 0.0 && o->depth_exponent < 1.0)) std::abort();
      if (o->depth_exponent > 0.0 && !(o->depth_reference > 0.0)) std::abort();
      if (o->machine.empty() || !o->machine.is_absolute() || o->speed_at.line <= 0) std::abort();
    }
  } catch (const lathectl::io::InputError&) {
  }
  return 0;
}
