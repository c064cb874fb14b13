#pragma once
// A JSON file lathectl reads back — `lathectl report`'s operation log (lathectl_oplog's
// operations.json), `lathectl compare`'s summary.json — with where each value is written, so a
// value found wrong after parsing is reported like a syntax error, at its line:
//   "FILE:LINE:COL: key 'rows[3].limit': expected a number"
//   "FILE:LINE:COL: not JSON: syntax error while parsing object - unexpected end of input; ..."
// Keys are named the way the TOML reader names them: "a.b", "rows[3]", "rows[3].limit".
// Nesting is bounded (kMaxDepth): a deeper file is refused, not recursed into.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>

namespace lathectl::io {

class JsonFile {
 public:
  static constexpr int kMaxDepth = 64;

  // Parses `text`, named `file` in messages. Throws InputError.
  JsonFile(std::string file, std::string_view text);
  // Reads and parses `file`; `what` names it when it cannot be read ("the operation log").
  static JsonFile read(const std::filesystem::path& file, const std::string& what);

  [[nodiscard]] const nlohmann::json& doc() const noexcept { return doc_; }
  [[nodiscard]] const std::string& file() const noexcept { return file_; }

  // "FILE:LINE:COL: key 'KEY': MESSAGE" at the value KEY names; a key the file does not write is
  // placed at the nearest enclosing value it does. KEY "" is the document itself.
  [[nodiscard]] std::string locate(const std::string& key, const std::string& message) const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  // Member `name` of `obj` (the value at key `key`): a finite number, a string, else fail().
  [[nodiscard]] double number(const nlohmann::json& obj, const std::string& key,
                              const char* name) const;
  [[nodiscard]] std::string text(const nlohmann::json& obj, const std::string& key,
                                 const char* name) const;
  // "KEY.name" ("name" at the document), "KEY[i]".
  [[nodiscard]] static std::string member(const std::string& key, std::string_view name);
  [[nodiscard]] static std::string element(const std::string& key, std::size_t i);

 private:
  std::string file_;
  nlohmann::json doc_;
  std::map<std::string, std::pair<int, int>, std::less<>> at_;  // key → line, column
  friend class JsonLocator;
};

}  // namespace lathectl::io
