#pragma once
// Reads a run's channels.csv back (lathectl compare): the format io::channels_csv writes — a
// header of unique, non-empty column names, then one row of numbers per sample (nan, inf, -inf
// as printf writes them). Read line by line from a stream, never as one string.

#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace lathectl::io {

struct ChannelTable {
  std::vector<std::string> names;           // header, in order
  std::vector<std::vector<double>> columns;  // one per name, all of the same length
};

// Throws InputError "FILE:LINE: column 'NAME': ..." (the header's line 1 for a bad name) for
// a bad header, a row with too few or too many fields, or a field that is not a number.
ChannelTable read_channels_csv(std::istream& in, const std::string& file);
ChannelTable read_channels_csv(const std::filesystem::path& file);

}  // namespace lathectl::io
