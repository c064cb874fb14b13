#include "lathectl/io/signal_file.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {

namespace {

[[noreturn]] void sig_fail(const std::string& file, int line, const std::string& message) {
  throw InputError(located(file, line, 0, message));
}

std::uint32_t sig_le32(std::string_view t, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 4; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(t[at + i]);
  return v;
}
std::uint16_t sig_le16(std::string_view t, std::size_t at) {
  return static_cast<std::uint16_t>(static_cast<unsigned char>(t[at]) |
                                    (static_cast<unsigned char>(t[at + 1]) << 8));
}

struct WavFormat {
  int tag = 0;  // 1 PCM, 3 IEEE float
  int channels = 0;
  std::uint32_t rate = 0;
  int bits = 0;
};

WavFormat wav_fmt(std::string_view c, const std::string& file) {
  if (c.size() < 16) sig_fail(file, 0, "WAV: the fmt chunk is shorter than 16 bytes");
  WavFormat f;
  f.tag = sig_le16(c, 0);
  f.channels = sig_le16(c, 2);
  f.rate = sig_le32(c, 4);
  f.bits = sig_le16(c, 14);
  if (f.tag == 0xFFFE) {  // WAVE_FORMAT_EXTENSIBLE: the sub-format GUID's first two bytes
    if (c.size() < 40) sig_fail(file, 0, "WAV: the extensible fmt chunk is shorter than 40 bytes");
    f.tag = sig_le16(c, 24);
  }
  if (f.tag != 1 && f.tag != 3)
    sig_fail(file, 0, "WAV: format " + std::to_string(f.tag) +
                      " is neither PCM (1) nor IEEE float (3); compressed WAV is not read");
  const bool pcm_ok = f.tag == 1 && (f.bits == 16 || f.bits == 24 || f.bits == 32);
  const bool float_ok = f.tag == 3 && (f.bits == 32 || f.bits == 64);
  if (!pcm_ok && !float_ok)
    sig_fail(file, 0, "WAV: " + std::to_string(f.bits) + "-bit " + (f.tag == 1 ? "PCM" : "float") +
                      " samples are not read (PCM 16, 24, 32; float 32, 64)");
  if (f.channels < 1) sig_fail(file, 0, "WAV: no channels");
  if (f.rate < 1 || f.rate > 10'000'000)
    sig_fail(file, 0, "WAV: sample rate " + std::to_string(f.rate) + " Hz is out of 1 … 1e7");
  return f;
}

double wav_sample(std::string_view d, std::size_t at, const WavFormat& f) {
  if (f.tag == 3 && f.bits == 32) {
    float v;
    const std::uint32_t u = sig_le32(d, at);
    std::memcpy(&v, &u, sizeof v);
    return v;
  }
  if (f.tag == 3) {
    const std::uint64_t u = sig_le32(d, at) | (std::uint64_t{sig_le32(d, at + 4)} << 32);
    double v;
    std::memcpy(&v, &u, sizeof v);
    return v;
  }
  if (f.bits == 16) return static_cast<std::int16_t>(sig_le16(d, at)) / 32768.0;
  if (f.bits == 24) {
    const std::uint32_t u = (static_cast<std::uint32_t>(sig_le16(d, at)) |
                             static_cast<std::uint32_t>(static_cast<unsigned char>(d[at + 2])) << 16)
                            << 8;
    return static_cast<std::int32_t>(u) / 2147483648.0;
  }
  return static_cast<std::int32_t>(sig_le32(d, at)) / 2147483648.0;
}

}  // namespace

Signal parse_wav(std::string_view t, const std::string& file, int channel) {
  if (t.size() < 12 || t.substr(0, 4) != "RIFF" || t.substr(8, 4) != "WAVE")
    sig_fail(file, 0, "not a WAV file (no RIFF/WAVE header)");
  WavFormat f;
  bool have_fmt = false;
  std::size_t at = 12;
  while (at + 8 <= t.size()) {
    const std::string_view id = t.substr(at, 4);
    const std::uint32_t size = sig_le32(t, at + 4);
    const std::size_t body = at + 8;
    if (id == "fmt ") {
      if (size > t.size() - body) sig_fail(file, 0, "WAV: the fmt chunk runs past the file's end");
      f = wav_fmt(t.substr(body, size), file);
      have_fmt = true;
    } else if (id == "data") {
      if (!have_fmt) sig_fail(file, 0, "WAV: the data chunk comes before the fmt chunk");
      if (channel < 0 || channel >= f.channels)
        sig_fail(file, 0, "WAV: channel " + std::to_string(channel) + " asked for, the file has " +
                          std::to_string(f.channels) + " (counted from 0)");
      // A recorder stopped before it could write the size (0 or 0xFFFFFFFF): the rest.
      const std::size_t have = t.size() - body;
      const std::size_t n_bytes = size == 0 || size == 0xFFFFFFFFu ? have : std::min<std::size_t>(size, have);
      const std::size_t width = static_cast<std::size_t>(f.bits / 8);
      const std::size_t frame = width * static_cast<std::size_t>(f.channels);
      const std::size_t frames = n_bytes / frame;
      if (frames < 2) sig_fail(file, 0, "WAV: fewer than 2 frames of samples");
      Signal s;
      s.rate_Hz = f.rate;
      s.unit = Signal::Unit::full_scale;
      s.samples.resize(frames);
      const std::size_t offset = body + width * static_cast<std::size_t>(channel);
      for (std::size_t k = 0; k < frames; ++k) {
        const double v = wav_sample(t, offset + k * frame, f);
        if (!std::isfinite(v))
          sig_fail(file, 0, "WAV: frame " + std::to_string(k) + " is not a finite number");
        s.samples[k] = v;
      }
      return s;
    }
    if (size > t.size() - body) break;
    at = body + size + (size & 1u);  // chunks are padded to even sizes
  }
  sig_fail(file, 0, have_fmt ? "WAV: no data chunk" : "WAV: no fmt chunk");
}

namespace {

bool csv_number(std::string_view s, double& v) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(v);
}

// "t,a" → the two numbers; false if the line is not exactly two finite numbers.
bool csv_row(std::string_view line, double& t, double& a) {
  const auto comma = line.find(',');
  if (comma == std::string_view::npos) return false;
  return csv_number(line.substr(0, comma), t) && csv_number(line.substr(comma + 1), a);
}

}  // namespace

Signal parse_signal_csv(std::string_view text, const std::string& file) {
  std::vector<double> times;
  Signal s;
  s.unit = Signal::Unit::m_per_s2;
  std::vector<int> lines;
  std::size_t pos = 0;
  int line_no = 0;
  bool first = true;
  while (pos < text.size()) {
    std::size_t stop = text.find('\n', pos);
    if (stop == std::string_view::npos) stop = text.size();
    std::string_view line = text.substr(pos, stop - pos);
    pos = stop + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    double t = 0.0, a = 0.0;
    if (!csv_row(line, t, a)) {
      if (first) {  // the header
        first = false;
        continue;
      }
      sig_fail(file, line_no, "expected a row `time_s,acceleration_m_s2` of two numbers");
    }
    first = false;
    if (!times.empty() && !(t > times.back()))
      sig_fail(file, line_no, "time " + std::to_string(t) + " s does not ascend");
    times.push_back(t);
    lines.push_back(line_no);
    s.samples.push_back(a);
  }
  if (times.size() < 2) sig_fail(file, line_no, "fewer than 2 rows of `time_s,acceleration_m_s2`");
  const double step = (times.back() - times.front()) / static_cast<double>(times.size() - 1);
  for (std::size_t k = 1; k < times.size(); ++k)
    if (std::abs(times[k] - times[k - 1] - step) > 0.01 * step)
      sig_fail(file, lines[k], "time step " + std::to_string(times[k] - times[k - 1]) +
                               " s is not the file's uniform step " + std::to_string(step) +
                               " s (within 1 %)");
  s.rate_Hz = 1.0 / step;
  if (!std::isfinite(s.rate_Hz)) sig_fail(file, lines.back(), "the rows' time step is zero");
  return s;
}

Signal read_signal_file(const std::string& path, int channel) {
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".wav" && ext != ".csv")
    throw InputError(path + ": a recorded signal is a .wav or a .csv file");
  const std::string text =
      read_input_file(path, ext == ".wav" ? "a signal (WAV)" : "a signal (CSV)", kMaxSignalBytes);
  if (ext == ".wav") return parse_wav(text, path, channel);
  if (channel != 0)
    throw InputError(path + ": a CSV signal has one channel (channel " + std::to_string(channel) +
                     " asked for)");
  return parse_signal_csv(text, path);
}

}  // namespace lathectl::io
