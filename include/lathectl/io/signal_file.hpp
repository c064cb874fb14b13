#pragma once
// A recorded vibration signal, for lathectl_vibsensor's --file (replay, tests): one channel of a
// WAV file (PCM 16, 24 or 32 bit, IEEE float 32 or 64, WAVE_FORMAT_EXTENSIBLE of either) or a CSV
// of `time,acceleration` rows. Read whole through the checked input path (io::read_input_file, at
// most kMaxSignalBytes); every refusal is an InputError naming the file (and the CSV's line).
//
// WAV samples are fractions of the interface's full scale (−1 … 1: an int sample over 2^(bits−1),
// a float as written); the caller scales them to volts and to m/s². A CSV holds the acceleration
// itself [m/s²]: an optional header line (the first line, if it is not two numbers), then rows
// `t,a` with t in seconds, ascending and uniformly spaced (the rate is (n − 1)/(t_last − t_first),
// each step within 1 % of its inverse), blank lines and lines starting with '#' skipped.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lathectl::io {

inline constexpr std::uintmax_t kMaxSignalBytes = 256u << 20;  // ~23 min of 48 kHz S32 mono

struct Signal {
  enum class Unit { full_scale, m_per_s2 };
  double rate_Hz = 0.0;
  Unit unit = Unit::full_scale;
  std::vector<double> samples;  // the one channel asked for
};

// `text` is the file's content, `file` its name for the messages; `channel` counts from 0 (a
// CSV has one). Throws InputError.
[[nodiscard]] Signal parse_wav(std::string_view text, const std::string& file, int channel);
[[nodiscard]] Signal parse_signal_csv(std::string_view text, const std::string& file);
// By the name's extension (.wav, .csv; any case): the checked read, then the parser.
[[nodiscard]] Signal read_signal_file(const std::string& path, int channel);

}  // namespace lathectl::io
