#pragma once
// Input errors: a user's mistake in a file or on the command line. Caught once at the program's
// top, printed as one message, exit code 2. The message names file, line and key.

#include <stdexcept>
#include <string>

namespace lathectl::io {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "file:line:col: message" (line/col omitted when 0).
[[nodiscard]] std::string located(const std::string& file, int line, int column,
                                  const std::string& message);

}  // namespace lathectl::io
