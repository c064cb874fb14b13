#include "lathectl/io/json_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {

using nlohmann::json;

class JsonLocator;

// The iterator the parser reads the text through: the locator's read position, so each SAX
// event knows where its token ended; at the end of the text held, a streamed file's next chunk
// is read (the end is the sentinel: equal to a cursor with nothing left to read).
struct JsonCursor {
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  JsonLocator* loc = nullptr;
  bool sentinel = false;
  reference operator*() const;
  JsonCursor& operator++();
  JsonCursor operator++(int) {
    JsonCursor c = *this;
    ++*this;
    return c;
  }
  bool operator==(const JsonCursor& o) const;
  bool operator!=(const JsonCursor& o) const { return !(*this == o); }
};

// SAX handler: builds the document (nlohmann's own DOM builder) and records where each key and
// array element is written. A token starts at the first character after the previous event's
// end that is not white space, ',' or ':' (the structural tokens that raise no event; the one
// character a number reads ahead is one of them or white space in any valid text).
// A streamed file is held a chunk at a time: before the next is read, the place of the token
// being looked for and the lines are counted up to the chunk's last few characters, which are
// kept (a parse error may point one character behind the read position).
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
  JsonLocator(JsonFile& f, InputStream& in, std::size_t chunk, const std::string& array,
              const JsonFile::Element& each, std::vector<std::string> keep)
      : f_(f),
        dom_(f.doc_, false),
        in_(&in),
        chunk_(std::max<std::size_t>(chunk, 1)),
        array_(array),
        each_(&each),
        keep_(std::move(keep)) {
    buf_.resize(chunk_ + kKeep);
    begin_ = end_ = read_ = last_ = counted_ = buf_.data();
  }
  JsonCursor begin() { return {this, false}; }
  JsonCursor end() { return {this, true}; }

  bool null() {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.null() && streamed(s);
  }
  bool boolean(bool v) {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.boolean(v) && streamed(s);
  }
  bool number_integer(json::number_integer_t v) {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.number_integer(v) && streamed(s);
  }
  bool number_unsigned(json::number_unsigned_t v) {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.number_unsigned(v) && streamed(s);
  }
  bool number_float(json::number_float_t v, const json::string_t& str) {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.number_float(v, str) && streamed(s);
  }
  bool string(json::string_t& v) {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.string(v) && streamed(s);
  }
  bool binary(json::binary_t& b) {
    if (skip_ > 0) return skipped();
    const bool s = value();
    return dom_.binary(b) && streamed(s);
  }
  bool start_object(std::size_t n) {
    const Open o = open(false);
    return o == Open::skip || (o == Open::build && dom_.start_object(n));
  }
  bool start_array(std::size_t n) {
    const Open o = open(true);
    return o == Open::skip || (o == Open::build && dom_.start_array(n));
  }
  bool end_object() {
    if (skip_ > 0) return close_skipped();
    const bool s = close();
    return dom_.end_object() && streamed(s);
  }
  bool end_array() {
    if (skip_ > 0) return close_skipped();
    const bool s = close();
    return dom_.end_array() && streamed(s);
  }
  bool key(json::string_t& k) {
    if (skip_ > 0) return skipped();
    const auto [line, col] = token_start();
    Frame& top = frames_.back();  // (its key's text reused: no allocation a member)
    top.key.assign(top.path);
    if (!top.key.empty()) top.key += '.';
    top.key += k;
    f_.at_.try_emplace(top.key, line, col);
    return dom_.key(k);
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    // position: characters read, the offending one last (one past the end: end of input).
    const std::uint64_t held_end = base_ + static_cast<std::uint64_t>(end_ - begin_);
    const std::uint64_t off = std::min<std::uint64_t>(position > 0 ? position - 1 : 0, held_end);
    const char* at = off >= base_ ? begin_ + (off - base_) : begin_;
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
  friend struct JsonCursor;
  static constexpr std::ptrdiff_t kKeep = 4;  // characters kept from one chunk to the next
  struct Frame {
    std::string path;
    bool array = false;
    std::size_t index = 0;
    std::string key;  // the member being read (objects)
  };
  JsonFile& f_;
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  InputStream* in_ = nullptr;  // streamed: the file, read a chunk at a time into buf_
  std::size_t chunk_ = 0;
  std::string buf_;
  bool eof_ = false;
  std::string array_;  // streamed: the member whose elements go to each_
  const JsonFile::Element* each_ = nullptr;
  const char* begin_ = nullptr;  // the text held (streamed: the chunk), at offset base_
  const char* end_ = nullptr;
  std::uint64_t base_ = 0;
  const char* read_ = nullptr;     // how far the lexer has read
  const char* last_ = nullptr;     // where the previous event's token ended
  const char* counted_ = nullptr;  // line_/col_ are those of this character
  int line_ = 1, col_ = 1;
  bool found_ = false;  // the next token's start, found before its chunk was dropped
  std::pair<int, int> found_at_;
  std::vector<Frame> frames_;
  std::vector<std::string> keep_;  // streamed: the other top-level members held
  int skip_ = 0;                   // > 0: that deep inside a value left out
  std::string error_;

  static bool blank(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',' || c == ':';
  }
  // Nothing left to read (a streamed file: after reading its next chunk).
  bool exhausted() { return read_ >= end_ && at_end(); }  // (per character: inlined)
  bool at_end() {
    if (in_ == nullptr || eof_) return true;
    refill();
    return read_ == end_;
  }
  void refill() {
    const char* cut = end_ - std::min(kKeep, end_ - begin_);
    if (!found_) {
      const char* p = last_;
      while (p < cut && blank(*p)) ++p;
      if (p < cut) {
        count_to(p);
        found_ = true;
        found_at_ = {line_, col_};
      }
    }
    last_ = std::max(last_, cut);
    if (counted_ < cut) count_to(cut);
    const std::ptrdiff_t off = cut - begin_;
    const std::size_t keep = static_cast<std::size_t>(end_ - cut);
    std::memmove(buf_.data(), cut, keep);
    last_ -= off;
    counted_ -= off;
    read_ -= off;
    base_ += static_cast<std::uint64_t>(off);
    const std::size_t n = in_->read(buf_.data() + keep, chunk_);
    end_ = begin_ + keep + n;
    eof_ = n == 0;
  }
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
    if (found_) {
      found_ = false;
      last_ = read_;
      return found_at_;
    }
    const char* p = last_;
    while (p < read_ && blank(*p)) ++p;
    last_ = read_;
    count_to(p);
    return {line_, col_};
  }
  // Line and column of the character at p (held), also behind the last place counted (a parse
  // error reported behind the last token).
  std::pair<int, int> position_of(const char* p) {
    if (p >= counted_) {
      count_to(p);
      return {line_, col_};
    }
    int line = line_;
    for (const char* q = p; q < counted_; ++q) line -= *q == '\n' ? 1 : 0;
    if (line == line_) return {line, col_ - static_cast<int>(counted_ - p)};
    const char* s = p;
    while (s > begin_ && s[-1] != '\n') --s;
    return {line, static_cast<int>(p - s) + 1};
  }
  void fail_at(const char* p, const std::string& message) {
    const auto [line, col] = position_of(p);
    error_ = located(f_.file_, line, col, message);
  }
  // The value starting (or ending) now is an element of the streamed array.
  bool in_streamed(std::size_t depth) const {
    return each_ != nullptr && frames_.size() == depth && !frames_[0].array && frames_[1].array &&
           frames_[1].path == array_;
  }
  // After the DOM took an element of the streamed array: handed on, then dropped with the
  // places of its values.
  bool streamed(bool s) {
    if (!s) return true;
    json& arr = f_.doc_[array_];
    const std::string key = JsonFile::element(array_, frames_[1].index - 1);
    (*each_)(f_, arr.back(), key);
    arr.get_ref<json::array_t&>().pop_back();
    auto it = f_.at_.lower_bound(key);
    while (it != f_.at_.end() && it->first.compare(0, key.size(), key) == 0) it = f_.at_.erase(it);
    return true;
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
    const bool s = in_streamed(2);
    (void)place();
    return s;
  }
  enum class Open { fail, build, skip };
  Open open(bool array) {
    if (skip_ > 0) (void)token_start();
    std::string k = skip_ > 0 ? std::string() : place();
    if (frames_.size() >= static_cast<std::size_t>(JsonFile::kMaxDepth)) {
      fail_at(read_ - 1, "nested deeper than " + std::to_string(JsonFile::kMaxDepth) + " levels");
      return Open::fail;
    }
    const bool skip = skip_ > 0 || left_out(array);
    frames_.push_back({skip ? std::string() : std::move(k), array, 0, {}});
    skip_ += skip ? 1 : 0;
    return skip ? Open::skip : Open::build;
  }
  // Streamed: an array or object opening now that nobody reads is left out of the document (its
  // key stays, with null): the document itself when it is an array, and the top-level members
  // other than the streamed array and keep_ (the streamed one too when it is not an array).
  bool left_out(bool array) const {
    if (each_ == nullptr) return false;
    if (frames_.empty()) return array;
    if (frames_.size() != 1 || frames_[0].array) return false;
    const std::string& name = frames_[0].key;
    if (name == array_) return !array;
    return std::find(keep_.begin(), keep_.end(), name) == keep_.end();
  }
  // Inside a value left out: only the places the next token is looked for from.
  bool skipped() {
    (void)token_start();
    return true;
  }
  bool close_skipped() {
    --skip_;
    found_ = false;
    last_ = read_;
    frames_.pop_back();
    return true;
  }
  bool close() {
    const bool s = in_streamed(3);
    found_ = false;
    last_ = read_;
    frames_.pop_back();
    return s;
  }
};

const char& JsonCursor::operator*() const {
  return *loc->read_;
}
JsonCursor& JsonCursor::operator++() {
  ++loc->read_;
  return *this;
}
bool JsonCursor::operator==(const JsonCursor& o) const {
  return (sentinel || loc->exhausted()) == (o.sentinel || o.loc->exhausted());
}

JsonFile::JsonFile(std::string file, std::string_view text) : file_(std::move(file)) {
  JsonLocator sax(*this, text);
  const bool ok = json::sax_parse(sax.begin(), sax.end(), &sax);
  sax.rethrow();
  if (!ok) throw InputError(located(file_, 0, 0, "not JSON"));
}

JsonFile JsonFile::read(const std::filesystem::path& file, const std::string& what) {
  return JsonFile(file.string(), read_input_file(file, what, kMaxJsonBytes));
}

JsonFile JsonFile::read_streamed(const std::filesystem::path& file, const std::string& what,
                                 std::uintmax_t max_bytes, const std::string& array,
                                 const Element& each, std::vector<std::string> keep,
                                 std::size_t chunk) {
  InputStream in(file, what, max_bytes);
  JsonFile f;
  f.file_ = file.string();
  {
    JsonLocator sax(f, in, chunk, array, each, std::move(keep));
    const bool ok = json::sax_parse(sax.begin(), sax.end(), &sax);
    sax.rethrow();
    if (!ok) throw InputError(located(f.file_, 0, 0, "not JSON"));
  }
  return f;
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
  const auto it = obj.find(name);  // (the member's key written only for a message)
  if (it == obj.end() || !it->is_number()) fail(member(key, name), "expected a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) fail(member(key, name), "expected a finite number");
  return v;
}

std::string JsonFile::text(const json& obj, const std::string& key, const char* name) const {
  if (!obj.is_object()) fail(key, "expected an object");
  const auto it = obj.find(name);
  if (it == obj.end() || !it->is_string()) fail(member(key, name), "expected a string");
  return it->get<std::string>();
}

std::string JsonFile::member(const std::string& key, std::string_view name) {
  return key.empty() ? std::string(name) : key + "." + std::string(name);
}

std::string JsonFile::element(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

}  // namespace lathectl::io
