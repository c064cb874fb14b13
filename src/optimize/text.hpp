#pragma once
// The few things lathectl optimize does to the program's text itself (everything it learns about
// the program comes from LinuxCNC's interpreter): marking lines for the interpreter, finding the
// keep marker, reading which words a line holds, and setting a line's F word. A line's words are
// read as LinuxCNC's lexer splits them: a letter and a number; comments "( … )" and "; …" are
// not words.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace lathectl::optimize {

// The longest line LinuxCNC 2.9's interpreter reads (LINELEN 255 with its terminator and
// newline; measured with rs274: 252 characters pass, 253 are "Command too long").
inline constexpr std::size_t kMaxLineChars = 252;

// The lines with "(lathectl-line N)" on each line that may carry a comment (not on blank lines,
// '%' lines or o-word lines; on a line of its own just before a line it would make too long),
// and "M3 S<rpm>" in front when rpm > 0 (as scripts/linuxcnc-sim).
std::vector<std::string> marked_lines(const std::vector<std::string>& lines, double rpm);

// "(lathectl:keep)" anywhere in the line (any case): the line is never changed.
bool keep_marked(const std::string& line);

// "(lathectl:finish)" anywhere in the line (any case): a finishing cut whatever its depth.
bool finish_marked(const std::string& line);

// The line's words: letter (upper case) and the text of its value ("G" "71.1", "F" "#1").
struct Word {
  char letter;
  std::string value;
};
std::vector<Word> words(const std::string& line);

// The line with its F word's number set to `value` (or " F<value>" added before a ';' comment
// or at the end); nullopt when its F word is not a plain number (an expression or parameter).
std::optional<std::string> with_feed(const std::string& line, const std::string& value);

}  // namespace lathectl::optimize
