// channels.csv back into columns (channels_reader.hpp), for lathectl compare.
#include "lathectl/io/channels_reader.hpp"

#include <cctype>
#include <charconv>
#include <fstream>
#include <set>
#include <string_view>
#include <system_error>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {
namespace {

// Field `text` as a number: what std::to_chars / printf write, nothing else (no spaces, no "+").
bool parse_number(std::string_view text, double& v) {
  if (text.empty()) return false;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  return r.ec == std::errc{} && r.ptr == text.data() + text.size();
}

// The printable start of a field for a message (a fuzzer may feed anything).
std::string shown(std::string_view s) { return printable(s, 24); }

}  // namespace

ChannelTable read_channels_csv(std::istream& in, const std::string& file) {
  ChannelTable t;
  std::string line;
  if (!std::getline(in, line)) throw InputError(located(file, 1, 0, "empty: no header line"));
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::set<std::string, std::less<>> seen;
  for (std::size_t pos = 0;;) {
    const std::size_t comma = line.find(',', pos);
    const std::string name = line.substr(pos, comma == std::string::npos ? comma : comma - pos);
    const std::string where = "column " + std::to_string(t.names.size() + 1);
    if (name.empty()) throw InputError(located(file, 1, 0, where + ": empty column name"));
    for (const char c : name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
        throw InputError(located(file, 1, 0, where + " '" + shown(name) +
                                                 "': a column name is letters, digits and _"));
    if (!seen.insert(name).second)
      throw InputError(located(file, 1, 0, where + " '" + printable(name) + "': named twice"));
    t.names.push_back(name);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  t.columns.resize(t.names.size());
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) {  // only at the end: a blank line inside the data is an error
      if (in.peek() == std::char_traits<char>::eof()) break;
      throw InputError(located(file, line_no, 0, "empty line"));
    }
    std::size_t pos = 0;
    for (std::size_t c = 0; c < t.names.size(); ++c) {
      if (pos > line.size())
        throw InputError(located(file, line_no, 0,
                                 "column '" + printable(t.names[c]) + "': missing (" + std::to_string(c) +
                                     " of " + std::to_string(t.names.size()) + " fields)"));
      const std::size_t comma = line.find(',', pos);
      const std::size_t end = comma == std::string::npos ? line.size() : comma;
      const std::string_view field(line.data() + pos, end - pos);
      double v = 0.0;
      if (!parse_number(field, v))
        throw InputError(located(file, line_no, 0,
                                 "column '" + printable(t.names[c]) + "': expected a number, got '" +
                                     shown(field) + "'"));
      t.columns[c].push_back(v);
      pos = comma == std::string::npos ? line.size() + 1 : comma + 1;
    }
    if (pos <= line.size())
      throw InputError(located(file, line_no, 0,
                               "more fields than the " + std::to_string(t.names.size()) +
                                   " columns of the header"));
  }
  if (in.bad()) throw InputError(located(file, line_no, 0, "read error"));
  return t;
}

ChannelTable read_channels_csv(const std::filesystem::path& file) {
  check_input_file(file, "a channels.csv", kMaxCsvBytes);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot read");
  return read_channels_csv(in, file.string());
}

}  // namespace lathectl::io
