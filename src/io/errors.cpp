#include "lathectl/io/errors.hpp"

#include <algorithm>

namespace lathectl::io {

namespace {
// The length of the UTF-8 sequence starting at s[i] (2–4), 0 when it is not one or encodes a C1
// control, an overlong form, a surrogate or a code point above U+10FFFF.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const unsigned c = b(0);
  const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3
                        : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((b(k) & 0xC0u) != 0x80u) return 0;
  if (c == 0xC2 && b(1) < 0xA0) return 0;              // U+0080–U+009F: C1 controls
  if (c == 0xE0 && b(1) < 0xA0) return 0;              // overlong
  if (c == 0xED && b(1) >= 0xA0) return 0;             // surrogates
  if (c == 0xF0 && b(1) < 0x90) return 0;              // overlong
  if (c == 0xF4 && b(1) >= 0x90) return 0;             // above U+10FFFF
  return n;
}
}  // namespace

std::string printable(std::string_view text, std::size_t max_chars) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(std::min(text.size(), max_chars * 4) + 4);
  std::size_t chars = 0, i = 0;
  for (; i < text.size() && chars < max_chars; ++chars) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t n = c >= 0x80 ? utf8_length(text, i) : 0; n > 0) {
      out.append(text.substr(i, n));
      i += n;
    } else {
      out += {'\\', 'x', kHex[c >> 4], kHex[c & 0xFu]};
      ++i;
    }
  }
  if (i < text.size()) out += "…";
  return out;
}

std::string error_line(std::string_view message) { return printable(message, kMaxErrorLineChars); }

std::string located(const std::string& file, int line, int column, const std::string& message) {
  std::string s = file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  return s + ": " + message;
}

std::string KeyLocations::locate(const std::string& key, const std::string& message) const {
  if (const auto it = at_.find(key); it != at_.end())
    return located(file_, it->second.first, it->second.second, "key '" + key + "': " + message);
  // Not written: the default applies. Point at the nearest enclosing table that is written.
  std::string parent = key;
  while (true) {
    const auto dot = parent.find_last_of(".[");
    if (dot == std::string::npos) break;
    parent.resize(dot);
    if (const auto it = at_.find(parent); it != at_.end())
      return located(file_, it->second.first, it->second.second,
                     "key '" + key + "' (not set in [" + parent + "]; its default applies): " +
                         message);
  }
  return located(file_, 0, 0, "key '" + key + "' (not set; its default applies): " + message);
}

void KeyLocations::fail(const std::string& key, const std::string& message) const {
  throw InputError(locate(key, message));
}

}  // namespace lathectl::io
