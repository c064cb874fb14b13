#pragma once
// Reads a run's channels.csv back (lathectl compare): the format io::channels_csv writes — a
// header of unique, non-empty column names, then one row of numbers per sample (nan, inf, -inf
// as printf writes them). Read line by line from a stream, never as one string: one line is held
// at a time (at most kMaxChannelsLineBytes), so streamed, memory does not grow with the file.

#include <cstddef>
#include <filesystem>
#include <istream>
#include <span>
#include <string>
#include <vector>

namespace lathectl::io {

// The longest line of a channels.csv (a row of thousands of channels is under 100 kB); a longer
// one (a file that is not a channels.csv, say a sparse one of NUL bytes) is refused at its line.
inline constexpr std::size_t kMaxChannelsLineBytes = std::size_t{1} << 20;

// Receives a channels.csv as it is read: the header once, then each row (header().size() values).
class ChannelRowSink {
 public:
  virtual ~ChannelRowSink() = default;
  virtual void header(const std::vector<std::string>& names) = 0;
  virtual void row(std::span<const double> values) = 0;
};

struct ChannelTable {
  std::vector<std::string> names;           // header, in order
  std::vector<std::vector<double>> columns;  // one per name, all of the same length
};

// Throws InputError "FILE:LINE: column 'NAME': ..." (the header's line 1 for a bad name) for
// a bad header, a row with too few or too many fields, a field that is not a number, or a line
// longer than kMaxChannelsLineBytes. The rows before a bad one have reached the sink.
void read_channels_csv(std::istream& in, const std::string& file, ChannelRowSink& sink);
void read_channels_csv(const std::filesystem::path& file, ChannelRowSink& sink);
// The whole table, held as columns (for the files read whole: session reports, verify).
ChannelTable read_channels_csv(std::istream& in, const std::string& file);
ChannelTable read_channels_csv(const std::filesystem::path& file);

}  // namespace lathectl::io
