// channels.csv back, row by row or into columns (channels_reader.hpp), for lathectl compare.
#include "lathectl/io/channels_reader.hpp"

#include <cctype>
#include <charconv>
#include <fstream>
#include <set>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

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

// The next line into `line` (a view into buf, without its '\n' and a '\r' before it); false at
// the end. A line that does not fit buf (kMaxChannelsLineBytes) is an InputError at its number.
bool next_line(std::istream& in, std::vector<char>& buf, std::string_view& line,
               const std::string& file, int line_no) {
  in.getline(buf.data(), static_cast<std::streamsize>(buf.size()));
  const auto n = static_cast<std::size_t>(in.gcount());
  if (in.fail() && !in.bad()) {
    if (n == 0 && in.eof()) return false;
    throw InputError(located(file, line_no, 0,
                             "a line longer than " +
                                 std::to_string(kMaxChannelsLineBytes >> 20) +
                                 " MiB: not a channels.csv (one row of numbers a line)"));
  }
  if (n == 0) return false;  // a read error (in.bad(): the caller says so)
  std::size_t len = in.eof() ? n : n - 1;  // the '\n' was extracted, not stored
  if (len > 0 && buf[len - 1] == '\r') --len;
  line = std::string_view(buf.data(), len);
  return true;
}

// The header's column names: letters, digits and _, unique.
std::vector<std::string> header_names(std::string_view line, const std::string& file) {
  std::vector<std::string> names;
  std::set<std::string, std::less<>> seen;
  for (std::size_t pos = 0;;) {
    const std::size_t comma = line.find(',', pos);
    const std::string name(
        line.substr(pos, comma == std::string_view::npos ? comma : comma - pos));
    const std::string where = "column " + std::to_string(names.size() + 1);
    if (name.empty()) throw InputError(located(file, 1, 0, where + ": empty column name"));
    for (const char c : name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
        throw InputError(located(file, 1, 0, where + " '" + shown(name) +
                                                 "': a column name is letters, digits and _"));
    if (!seen.insert(name).second)
      throw InputError(located(file, 1, 0, where + " '" + printable(name) + "': named twice"));
    names.push_back(name);
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return names;
}

// The rows held as columns.
struct TableSink final : ChannelRowSink {
  ChannelTable table;
  void header(const std::vector<std::string>& names) override {
    table.names = names;
    table.columns.resize(names.size());
  }
  void row(std::span<const double> values) override {
    for (std::size_t c = 0; c < values.size(); ++c) table.columns[c].push_back(values[c]);
  }
};

}  // namespace

void read_channels_csv(std::istream& in, const std::string& file, ChannelRowSink& sink) {
  std::vector<char> buf(kMaxChannelsLineBytes + 2);  // a longer line fills it: refused
  int line_no = 1;
  std::string_view line;
  if (!next_line(in, buf, line, file, line_no))
    throw InputError(located(file, 1, 0, "empty: no header line"));
  const std::vector<std::string> names = header_names(line, file);
  sink.header(names);
  std::vector<double> values(names.size());
  while (next_line(in, buf, line, file, ++line_no)) {
    if (line.empty()) {  // only at the end: a blank line inside the data is an error
      if (in.peek() == std::char_traits<char>::eof()) break;
      throw InputError(located(file, line_no, 0, "empty line"));
    }
    std::size_t pos = 0;
    for (std::size_t c = 0; c < names.size(); ++c) {
      if (pos > line.size())
        throw InputError(located(file, line_no, 0,
                                 "column '" + printable(names[c]) + "': missing (" +
                                     std::to_string(c) + " of " + std::to_string(names.size()) +
                                     " fields)"));
      const std::size_t comma = line.find(',', pos);
      const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
      const std::string_view field = line.substr(pos, end - pos);
      if (!parse_number(field, values[c]))
        throw InputError(located(file, line_no, 0,
                                 "column '" + printable(names[c]) + "': expected a number, got '" +
                                     shown(field) + "'"));
      pos = comma == std::string_view::npos ? line.size() + 1 : comma + 1;
    }
    if (pos <= line.size())
      throw InputError(located(file, line_no, 0,
                               "more fields than the " + std::to_string(names.size()) +
                                   " columns of the header"));
    sink.row(values);
  }
  if (in.bad()) throw InputError(located(file, line_no, 0, "read error"));
}

void read_channels_csv(const std::filesystem::path& file, ChannelRowSink& sink) {
  check_input_file(file, "a channels.csv", kMaxCsvBytes);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot read");
  read_channels_csv(in, file.string(), sink);
}

ChannelTable read_channels_csv(std::istream& in, const std::string& file) {
  TableSink sink;
  read_channels_csv(in, file, sink);
  return std::move(sink.table);
}

ChannelTable read_channels_csv(const std::filesystem::path& file) {
  TableSink sink;
  read_channels_csv(file, sink);
  return std::move(sink.table);
}

}  // namespace lathectl::io
