#pragma once
// Input errors: a user's mistake in a file or on the command line. Caught once at the program's
// top, printed as one message, exit code 2. The message names file, line and key.

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace lathectl::io {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Text from a file or a command line made safe for one line on a terminal: every control byte
// (C0, DEL, the C1 controls U+0080–U+009F, whose CSI starts escape sequences as ESC [ does) and
// every byte that is not UTF-8 written as \xNN (ESC as \x1b, a newline as \x0a), valid UTF-8
// kept (µ, ·, →); cut after `max_chars` characters with "…". What a reader quotes from its
// input goes through it (kMaxQuotedChars), and the program's one error line does again
// (error_line: kMaxErrorLineChars), so no reader can echo an escape or a 10 MB line raw.
inline constexpr std::size_t kMaxQuotedChars = 200;
inline constexpr std::size_t kMaxErrorLineChars = 1000;
[[nodiscard]] std::string printable(std::string_view text,
                                    std::size_t max_chars = kMaxQuotedChars);
// The message as the program prints it after "error: ": printable(message, kMaxErrorLineChars).
[[nodiscard]] std::string error_line(std::string_view message);

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
