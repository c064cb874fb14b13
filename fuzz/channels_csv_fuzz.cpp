// libFuzzer target for the channels.csv reader (`lathectl compare`): any input must either read
// into columns of one length, one per unique header name, or throw InputError located in the file.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <string_view>

#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const auto t = lathectl::io::read_channels_csv(in, "fuzz.csv");
    if (t.names.empty() || t.columns.size() != t.names.size()) std::abort();
    for (const auto& c : t.columns)
      if (c.size() != t.columns[0].size()) std::abort();
    if (std::set<std::string>(t.names.begin(), t.names.end()).size() != t.names.size())
      std::abort();
  } catch (const lathectl::io::InputError& e) {
    if (std::string_view(e.what()).rfind("fuzz.csv", 0) != 0) std::abort();
  }
  return 0;
}
