#include "lathectl/io/json_file.hpp"

#include <cmath>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {

using nlohmann::json;

// The iterator the parser reads the text through: it keeps how far the lexer has read, so each
// SAX event knows where its token ended.
struct JsonCursor {
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  const char* p = nullptr;
  const char** read = nullptr;
  reference operator*() const { return *p; }
  JsonCursor& operator++() {
    *read = ++p;
    return *this;
  }
  JsonCursor operator++(int) {
    JsonCursor c = *this;
    ++*this;
    return c;
  }
  bool operator==(const JsonCursor& o) const { return p == o.p; }
  bool operator!=(const JsonCursor& o) const { return p != o.p; }
};

// SAX handler: builds the document (nlohmann's own DOM builder) and records where each key and
// array element is written. A token starts at the first character after the previous event's
// end that is not white space, ',' or ':' (the structural tokens that raise no event; the one
// character a number reads ahead is one of them or white space in any valid text).
class JsonLocator {
 public:
  JsonLocator(JsonFile& f, std::string_view text)
      : f_(f),
        dom_(f.doc_, false),
        begin_(text.data()),
        end_(text.data() + text.size()),
        read_(text.data()),
        last_(text.data()),
        counted_(text.data()) {}
  JsonCursor begin() { return {begin_, &read_}; }
  JsonCursor end() { return {end_, &read_}; }

  bool null() { return value() && dom_.null(); }
  bool boolean(bool v) { return value() && dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return value() && dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value() && dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) {
    return value() && dom_.number_float(v, s);
  }
  bool string(json::string_t& s) { return value() && dom_.string(s); }
  bool binary(json::binary_t& b) { return value() && dom_.binary(b); }
  bool start_object(std::size_t n) { return open(false) && dom_.start_object(n); }
  bool start_array(std::size_t n) { return open(true) && dom_.start_array(n); }
  bool end_object() { return close() && dom_.end_object(); }
  bool end_array() { return close() && dom_.end_array(); }
  bool key(json::string_t& k) {
    const auto [line, col] = token_start();
    frames_.back().key = JsonFile::member(frames_.back().path, k);
    f_.at_.try_emplace(frames_.back().key, line, col);
    return dom_.key(k);
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    // position: characters read, the offending one last (one past the end: end of input).
    const std::size_t size = static_cast<std::size_t>(end_ - begin_);
    const char* at = begin_ + std::min(position > 0 ? position - 1 : 0, size);
    std::string what = e.what();  // "[json.exception.parse_error.101] parse error at line 2, ..."
    if (const auto c = what.find("column "); c != std::string::npos) {
      if (const auto colon = what.find(": ", c); colon != std::string::npos)
        what = what.substr(colon + 2);
    }
    fail_at(at, "not JSON: " + what);
    return false;
  }

  // After sax_parse: the error it stopped at, if any.
  void rethrow() const {
    if (!error_.empty()) throw InputError(error_);
  }

 private:
  struct Frame {
    std::string path;
    bool array = false;
    std::size_t index = 0;
    std::string key;  // the member being read (objects)
  };
  JsonFile& f_;
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  const char* begin_;
  const char* end_;
  const char* read_;     // how far the lexer has read
  const char* last_;     // where the previous event's token ended
  const char* counted_;  // line_/col_ are those of this character
  int line_ = 1, col_ = 1;
  std::vector<Frame> frames_;
  std::string error_;

  void count_to(const char* p) {
    for (; counted_ < p; ++counted_) {
      if (*counted_ == '\n') {
        ++line_;
        col_ = 1;
      } else {
        ++col_;
      }
    }
  }
  std::pair<int, int> token_start() {
    const char* p = last_;
    while (p < read_ &&
           (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',' || *p == ':'))
      ++p;
    last_ = read_;
    count_to(p);
    return {line_, col_};
  }
  void fail_at(const char* p, const std::string& message) {
    if (p < counted_) {  // (a parse error reported behind the last token: count afresh)
      counted_ = begin_;
      line_ = col_ = 1;
    }
    count_to(p);
    error_ = located(f_.file_, line_, col_, message);
  }
  // The key of the value starting now (recorded for array elements and the document; an
  // object's member was recorded at its key).
  std::string place() {
    const auto [line, col] = token_start();
    if (frames_.empty()) {
      f_.at_.try_emplace(std::string(), line, col);
      return std::string();
    }
    Frame& top = frames_.back();
    if (!top.array) return top.key;
    std::string k = JsonFile::element(top.path, top.index++);
    f_.at_.try_emplace(k, line, col);
    return k;
  }
  bool value() {
    (void)place();
    return true;
  }
  bool open(bool array) {
    std::string k = place();
    if (frames_.size() >= static_cast<std::size_t>(JsonFile::kMaxDepth)) {
      fail_at(read_ - 1, "nested deeper than " + std::to_string(JsonFile::kMaxDepth) + " levels");
      return false;
    }
    frames_.push_back({std::move(k), array, 0, {}});
    return true;
  }
  bool close() {
    last_ = read_;
    frames_.pop_back();
    return true;
  }
};

JsonFile::JsonFile(std::string file, std::string_view text) : file_(std::move(file)) {
  JsonLocator sax(*this, text);
  const bool ok = json::sax_parse(sax.begin(), sax.end(), &sax);
  sax.rethrow();
  if (!ok) throw InputError(located(file_, 0, 0, "not JSON"));
}

JsonFile JsonFile::read(const std::filesystem::path& file, const std::string& what) {
  return JsonFile(file.string(), read_input_file(file, what, kMaxJsonBytes));
}

std::string JsonFile::locate(const std::string& key, const std::string& message) const {
  const std::string named = key.empty() ? message : "key '" + key + "': " + message;
  if (const auto it = at_.find(key); it != at_.end())
    return located(file_, it->second.first, it->second.second, named);
  // Not written: point at the nearest enclosing value that is.
  std::string parent = key;
  while (!parent.empty()) {
    const auto cut = parent.find_last_of(".[");
    parent.resize(cut == std::string::npos ? 0 : cut);
    if (const auto it = at_.find(parent); it != at_.end())
      return located(
          file_, it->second.first, it->second.second,
          "key '" + key + "' (missing" + (parent.empty() ? "" : " in " + parent) + "): " + message);
  }
  return located(file_, 0, 0, named);
}

void JsonFile::fail(const std::string& key, const std::string& message) const {
  throw InputError(locate(key, message));
}

double JsonFile::number(const json& obj, const std::string& key, const char* name) const {
  if (!obj.is_object()) fail(key, "expected an object");
  const std::string k = member(key, name);
  const auto it = obj.find(name);
  if (it == obj.end() || !it->is_number()) fail(k, "expected a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) fail(k, "expected a finite number");
  return v;
}

std::string JsonFile::text(const json& obj, const std::string& key, const char* name) const {
  if (!obj.is_object()) fail(key, "expected an object");
  const std::string k = member(key, name);
  const auto it = obj.find(name);
  if (it == obj.end() || !it->is_string()) fail(k, "expected a string");
  return it->get<std::string>();
}

std::string JsonFile::member(const std::string& key, std::string_view name) {
  return key.empty() ? std::string(name) : key + "." + std::string(name);
}

std::string JsonFile::element(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

}  // namespace lathectl::io
