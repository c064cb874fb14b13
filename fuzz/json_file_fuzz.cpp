// libFuzzer target for the JSON files lathectl reads back (io::JsonFile: `lathectl report`'s
// operation log through io::read_operation_log, `lathectl compare`'s summary.json): any input
// either reads, into the document nlohmann's own parser makes of it, or throws one InputError
// located in the file ("fuzz.json:LINE:COL: ...", a line of the text).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/json_file.hpp"
#include "lathectl/io/operation_log.hpp"

namespace {
// "fuzz.json:L:C: ..." with 1 ≤ L ≤ the text's lines.
void check_located(std::string_view msg, std::string_view text) {
  constexpr std::string_view kFile = "fuzz.json:";
  if (msg.rfind(kFile, 0) != 0) std::abort();
  const std::size_t lines =
      1 + static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  std::size_t line = 0, i = kFile.size();
  for (; i < msg.size() && msg[i] >= '0' && msg[i] <= '9' && line <= lines; ++i)
    line = line * 10 + static_cast<std::size_t>(msg[i] - '0');
  if (line < 1 || line > lines || i >= msg.size() || msg[i] != ':') std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  bool parsed = false;
  try {
    const lathectl::io::JsonFile f("fuzz.json", text);
    parsed = true;
    if (f.doc() != nlohmann::json::parse(text)) std::abort();  // the same document
    (void)lathectl::io::read_operation_log(f);
  } catch (const lathectl::io::InputError& e) {
    check_located(e.what(), text);
    const std::string_view msg = e.what();
    // A syntax error is one for nlohmann's parser too (the nesting bound is lathectl's own).
    if (!parsed && msg.find("nested deeper") == std::string_view::npos &&
        nlohmann::json::accept(text))
      std::abort();
  } catch (const nlohmann::json::exception&) {
    std::abort();  // a reader let one of nlohmann's exceptions through: exit 1, not 2
  }
  return 0;
}
