#include "lathectl/io/errors.hpp"

namespace lathectl::io {

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
