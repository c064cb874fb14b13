#pragma once
// A JSON file lathectl reads back — `lathectl report`'s operation log (lathectl_oplog's
// operations.json), `lathectl compare`'s summary.json — with where each value is written, so a
// value found wrong after parsing is reported like a syntax error, at its line:
//   "FILE:LINE:COL: key 'rows[3].limit': expected a number"
//   "FILE:LINE:COL: not JSON: syntax error while parsing object - unexpected end of input; ..."
// Keys are named the way the TOML reader names them: "a.b", "rows[3]", "rows[3].limit".
// Nesting is bounded (kMaxDepth): a deeper file is refused, not recursed into.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lathectl::io {

class JsonFile {
 public:
  static constexpr int kMaxDepth = 64;

  // Parses `text`, named `file` in messages. Throws InputError.
  JsonFile(std::string file, std::string_view text);
  // Reads and parses `file`; `what` names it when it cannot be read ("the operation log").
  static JsonFile read(const std::filesystem::path& file, const std::string& what);

  // Each element of the document's array member `array` ("rows"), handed to `each` as soon as it
  // is read — with its key ("rows[3]") and the file, whose locate() and fail() place it and its
  // members — and then dropped, with the places of its values. Called from within the parse.
  using Element = std::function<void(const JsonFile&, const nlohmann::json&, const std::string&)>;
  // Reads `file` a chunk at a time through the checked input path (io::InputStream, at most
  // `max_bytes`) and parses it as the constructor does, except that the elements of `array` are
  // streamed to `each` and left out of doc() (there an empty array): memory does not grow with
  // them. Of the other top-level members only those named in `keep` keep an array or object
  // value (the others, a document that is an array and an `array` that is not one: null), so no
  // shape of the file makes it held whole. (`chunk` bytes are read at a time: a test cuts the
  // text anywhere.)
  static JsonFile read_streamed(const std::filesystem::path& file, const std::string& what,
                                std::uintmax_t max_bytes, const std::string& array,
                                const Element& each, std::vector<std::string> keep,
                                std::size_t chunk = std::size_t{1} << 20);

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
  JsonFile() = default;
  friend class JsonLocator;
};

}  // namespace lathectl::io
