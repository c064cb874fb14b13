// libFuzzer target for LinuxCNC's tool table as lathectl optimize reads it (--tool-table,
// io/tool_file.hpp read_tool_table): any input either reads into tools with a number and a
// line of the file, each number once, or fails with an InputError naming the file. The table is
// then applied to a tool file's tools as optimize does (apply_tool_table), which may refuse a
// nose radius that disagrees, by name, but must not crash. Its corpus (fuzz/regressions/
// tool_table/) holds issue 49's classes: a byte-order mark, CRLF lines, huge numbers, duplicates.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/tool_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lathectl;
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<io::TableTool> table;
  try {
    table = io::read_tool_table(text, "fuzz.tbl");
  } catch (const io::InputError& e) {
    if (std::string_view(e.what()).find("fuzz.tbl") == std::string_view::npos) std::abort();
    return 0;
  }
  std::unordered_set<int> seen;
  for (const auto& t : table)
    if (t.line < 1 || !seen.insert(t.number).second) std::abort();  // a duplicate let through
  std::vector<io::ToolSpec> specs(2);
  specs[0].number = 1;
  specs[0].nose_radius_mm = 0.4;
  specs[1].number = 2;
  try {
    io::apply_tool_table(specs, table, "tools.toml", "fuzz.tbl");
  } catch (const io::InputError&) {
  }
  return 0;
}
