#include "optimize/text.hpp"

#include <cctype>
#include <cstdio>
#include <utility>

#include "lathectl/io/canon.hpp"

namespace lathectl::optimize {
namespace {

bool is_blank(const std::string& s) {
  for (char c : s)
    if (c != ' ' && c != '\t') return false;
  return true;
}

// Where the line's ';' comment starts (outside parentheses), or its end.
std::size_t code_end(const std::string& l) {
  int depth = 0;
  for (std::size_t i = 0; i < l.size(); ++i) {
    if (l[i] == '(') ++depth;
    if (l[i] == ')' && depth > 0) --depth;
    if (l[i] == ';' && depth == 0) return i;
  }
  return l.size();
}

// Scans the words outside comments: calls f(letter, value_begin, value_end).
template <class F>
void scan(const std::string& l, F&& f) {
  const std::size_t end = code_end(l);
  std::size_t i = 0;
  while (i < end) {
    const char c = l[i];
    if (c == '(') {
      while (i < end && l[i] != ')') ++i;
      ++i;
      continue;
    }
    if (std::isalpha(static_cast<unsigned char>(c))) {
      std::size_t j = i + 1;
      while (j < end && (l[j] == ' ' || l[j] == '\t')) ++j;
      std::size_t k = j;
      if (k < end && (l[k] == '[' || l[k] == '#' || l[k] == '<')) {  // expression / parameter
        int depth = 0;
        for (; k < end; ++k) {
          if (l[k] == '[') ++depth;
          if (l[k] == ']') --depth;
          if (depth <= 0 && k > j &&
              (std::isalpha(static_cast<unsigned char>(l[k])) || l[k] == '('))
            break;
        }
      } else {
        while (k < end && (std::isdigit(static_cast<unsigned char>(l[k])) || l[k] == '.' ||
                           l[k] == '-' || l[k] == '+' || l[k] == ' '))
          ++k;
      }
      f(static_cast<char>(std::toupper(static_cast<unsigned char>(c))), j, k);
      i = k > i + 1 ? k : i + 1;
      continue;
    }
    ++i;
  }
}

}  // namespace

std::vector<std::string> marked_lines(const std::vector<std::string>& lines, double rpm) {
  std::vector<std::string> out;
  out.reserve(lines.size() + 1);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    std::size_t k = 0;
    while (k < l.size() && (l[k] == ' ' || l[k] == '\t')) ++k;
    const bool first_percent = i == 0 && k < l.size() && l[k] == '%';
    if (rpm > 0.0 && i == 0 && !first_percent) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "M3 S%.6g", rpm);
      out.emplace_back(buf);
    }
    const auto w = words(l);
    const bool o_word = !w.empty() && (w[0].letter == 'O' ||
                                       (w[0].letter == 'N' && w.size() > 1 && w[1].letter == 'O'));
    if (is_blank(l) || (k < l.size() && l[k] == '%') || o_word) {
      out.push_back(l);
    } else {
      const std::size_t at = code_end(l);
      const std::string marker = "(" + io::canon_line_marker(static_cast<int>(i + 1)) + ")";
      std::string marked = l.substr(0, at) + " " + marker + l.substr(at);
      // rs274 refuses a line longer than kMaxLineChars ("Command too long"): a valid line that
      // the marker would push past it gets the marker on a line of its own just before it (a
      // comment line sets the line of the moves that follow as well).
      if (marked.size() > kMaxLineChars) {
        out.push_back(marker);
        marked = l;
      }
      out.push_back(std::move(marked));
    }
    if (rpm > 0.0 && first_percent) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "M3 S%.6g", rpm);
      out.emplace_back(buf);
    }
  }
  return out;
}

namespace {
bool has_marker(const std::string& line, const char* marker) {
  std::string low;
  for (char c : line)
    if (c != ' ' && c != '\t')
      low += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return low.find(marker) != std::string::npos;
}
}  // namespace

bool keep_marked(const std::string& line) { return has_marker(line, "(lathectl:keep)"); }
bool finish_marked(const std::string& line) { return has_marker(line, "(lathectl:finish)"); }

std::vector<Word> words(const std::string& line) {
  std::vector<Word> out;
  scan(line, [&](char letter, std::size_t b, std::size_t e) {
    std::string v;
    for (std::size_t i = b; i < e; ++i)
      if (line[i] != ' ' && line[i] != '\t') v += line[i];
    out.push_back({letter, v});
  });
  return out;
}

std::optional<std::string> with_feed(const std::string& line, const std::string& value) {
  std::size_t fb = std::string::npos, fe = 0;
  bool plain = true;
  scan(line, [&](char letter, std::size_t b, std::size_t e) {
    if (letter != 'F') return;
    fb = b;
    fe = e;
    plain = b < e && (std::isdigit(static_cast<unsigned char>(line[b])) || line[b] == '.');
  });
  if (fb != std::string::npos) {
    if (!plain) return std::nullopt;
    while (fe > fb && (line[fe - 1] == ' ' || line[fe - 1] == '\t')) --fe;  // keep the spacing
    return line.substr(0, fb) + value + line.substr(fe);
  }
  std::size_t at = code_end(line);
  std::size_t b = at;
  while (b > 0 && (line[b - 1] == ' ' || line[b - 1] == '\t')) --b;
  return line.substr(0, b) + " F" + value + (at < line.size() ? " " : "") + line.substr(at);
}

}  // namespace lathectl::optimize
