#pragma once
// Input errors: a user's mistake in a file or on the command line. Caught once at the program's
// top, printed as one message, exit code 2. The message names file, line and key.

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace lathectl::io {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "file:line:col: message" (line/col omitted when 0).
[[nodiscard]] std::string located(const std::string& file, int line, int column,
                                  const std::string& message);

// Where a file wrote each key ("table.key", "table[2].key", and the tables themselves):
// recorded while the file is read (TableReader) and kept with what was read from it, so a check
// made later — across several keys once all are read, or by the rig the scenario configures —
// is reported at the key that decides it, like any other error in the file.
class KeyLocations {
 public:
  explicit KeyLocations(std::string file) : file_(std::move(file)) {}
  void record(const std::string& key, int line, int column) {
    at_.try_emplace(key, line, column);
  }
  // "file:line:col: key 'k': message". A key the file does not write (its default applies) is
  // placed at the nearest enclosing table the file writes, and the message says so.
  [[nodiscard]] std::string locate(const std::string& key, const std::string& message) const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::map<std::string, std::pair<int, int>, std::less<>> at_;
};

}  // namespace lathectl::io
