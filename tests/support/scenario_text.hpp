#pragma once
// An example scenario's text, and that text with one passage replaced: for tests that parse an
// edited example (the other settings tests have local copies of the same two functions).

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

namespace lathectl::test {

inline std::string example_text(const std::string& name) {
  std::ifstream in(LATHECTL_SOURCE_DIR "/examples/scenarios/" + name + ".toml", std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `text` with the first occurrence of `from` replaced by `to` (a test failure if absent).
inline std::string edited(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// `text` with `from`, which must occur exactly once, replaced by `to` (a test failure if absent
// or ambiguous).
inline std::string edited_once(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  EXPECT_EQ(text.find(from, pos + 1), std::string::npos) << "ambiguous edit: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// 1-based line of the first occurrence of `needle` in `text`.
inline int line_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  return 1 + static_cast<int>(
                 std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

}  // namespace lathectl::test
