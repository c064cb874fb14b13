// libFuzzer target for lathectl optimize's tool file (--tool-file, io/tool_file.hpp
// read_tool_file: a TOML [[tool]] list): any input either reads into tools, each number once,
// or fails with an InputError naming the file. Its corpus (fuzz/regressions/tool_file/) holds
// issue 49's classes: a byte-order mark, CRLF lines, huge numbers, duplicate tools.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <unordered_set>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/tool_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lathectl;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto tools = io::read_tool_file(text, "fuzz_tools.toml");
    std::unordered_set<int> seen;
    for (const auto& t : tools)
      if (!seen.insert(t.number).second) std::abort();  // a duplicate let through
  } catch (const io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz_tools.toml") == std::string_view::npos)
      std::abort();
  }
  return 0;
}
