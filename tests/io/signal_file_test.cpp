// lathectl_vibsensor's recorded signals (io/signal_file.hpp): WAV PCM 16/24/32 and float 32/64
// (plain and extensible) read to fractions of full scale, one channel of several; a CSV of
// time,acceleration to m/s² at its rate; every refusal names the file (and the CSV's line).
#include "lathectl/io/signal_file.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {
namespace {

void put(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}

// A WAV of `frames` interleaved frames (each value's little-endian bytes given by `raw`).
std::string wav(int tag, int channels, int bits, std::uint32_t rate, const std::string& data,
                bool extensible = false) {
  std::string fmt;
  put(fmt, extensible ? 0xFFFE : static_cast<unsigned>(tag), 2);
  put(fmt, static_cast<unsigned>(channels), 2);
  put(fmt, rate, 4);
  put(fmt, rate * static_cast<unsigned>(channels * bits / 8), 4);
  put(fmt, static_cast<unsigned>(channels * bits / 8), 2);
  put(fmt, static_cast<unsigned>(bits), 2);
  if (extensible) {
    put(fmt, 22, 2);
    put(fmt, static_cast<unsigned>(bits), 2);
    put(fmt, 0, 4);
    put(fmt, static_cast<unsigned>(tag), 2);
    fmt += std::string("\x00\x00\x00\x00\x10\x00\x80\x00\x00\xAA\x00\x38\x9B\x71", 14);
  }
  std::string body = "WAVE";
  body += "LIST";  // a chunk a reader must skip (odd size: padded)
  put(body, 3, 4);
  body += std::string("abc\0", 4);
  body += "fmt ";
  put(body, fmt.size(), 4);
  body += fmt;
  body += "data";
  put(body, data.size(), 4);
  body += data;
  std::string out = "RIFF";
  put(out, body.size(), 4);
  return out + body;
}

std::string error_of(auto&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SignalFile, WavPcm16ReadsTheChannelAskedForAsFullScaleFractions) {
  std::string d;
  for (int k = 0; k < 3; ++k) {
    put(d, static_cast<std::uint16_t>(static_cast<std::int16_t>(1000 * k)), 2);  // channel 0
    put(d, static_cast<std::uint16_t>(static_cast<std::int16_t>(-16384 * k / 2)), 2);
  }
  const Signal s = parse_wav(wav(1, 2, 16, 48000, d), "rec.wav", 1);
  EXPECT_EQ(s.rate_Hz, 48000.0);
  EXPECT_EQ(s.unit, Signal::Unit::full_scale);
  EXPECT_EQ(s.samples, (std::vector<double>{0.0, -0.25, -0.5}));
}

TEST(SignalFile, WavPcm24And32AndFloatPlainOrExtensible) {
  std::string d24, d32, f32, f64;
  put(d24, 0x400000, 3);  // +0.5
  put(d24, 0xC00000, 3);  // -0.5
  put(d32, 0x20000000, 4);
  put(d32, 0xE0000000, 4);
  for (float v : {0.75f, -1.5f}) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    put(f32, u, 4);
  }
  for (double v : {0.125, -2.0}) {
    std::uint64_t u;
    std::memcpy(&u, &v, 8);
    put(f64, u, 8);
  }
  EXPECT_EQ(parse_wav(wav(1, 1, 24, 44100, d24), "a.wav", 0).samples, (std::vector{0.5, -0.5}));
  EXPECT_EQ(parse_wav(wav(1, 1, 32, 44100, d32, true), "a.wav", 0).samples,
            (std::vector{0.25, -0.25}));
  EXPECT_EQ(parse_wav(wav(3, 1, 32, 96000, f32, true), "a.wav", 0).samples,
            (std::vector{0.75, -1.5}));
  EXPECT_EQ(parse_wav(wav(3, 1, 64, 96000, f64), "a.wav", 0).samples, (std::vector{0.125, -2.0}));
}

TEST(SignalFile, WavRefusalsNameTheFile) {
  std::string d(8, '\0');
  EXPECT_EQ(error_of([&] { (void)parse_wav("RIFX....WAVE", "x.wav", 0); }),
            "x.wav: not a WAV file (no RIFF/WAVE header)");
  EXPECT_NE(error_of([&] { (void)parse_wav(wav(1, 2, 16, 8000, d), "x.wav", 2); })
                .find("x.wav: WAV: channel 2 asked for, the file has 2"),
            std::string::npos);
  EXPECT_NE(error_of([&] { (void)parse_wav(wav(1, 1, 8, 8000, d), "x.wav", 0); })
                .find("x.wav: WAV: 8-bit PCM samples are not read"),
            std::string::npos);
  EXPECT_NE(error_of([&] { (void)parse_wav(wav(2, 1, 16, 8000, d), "x.wav", 0); })
                .find("x.wav: WAV: format 2 is neither PCM"),
            std::string::npos);
  const std::string whole = wav(1, 1, 16, 8000, d);
  EXPECT_EQ(error_of([&] { (void)parse_wav(whole.substr(0, 40), "x.wav", 0); }),
            "x.wav: WAV: the fmt chunk runs past the file's end");
}

TEST(SignalFile, CsvGivesMetresPerSecondSquaredAtItsRate) {
  const Signal s = parse_signal_csv(
      "time_s,acceleration_m_s2\n# a comment\n0,1.5\n0.0005,-2\r\n\n0.001,3e1\n", "a.csv");
  EXPECT_EQ(s.unit, Signal::Unit::m_per_s2);
  EXPECT_NEAR(s.rate_Hz, 2000.0, 1e-9);
  EXPECT_EQ(s.samples, (std::vector{1.5, -2.0, 30.0}));
}

TEST(SignalFile, CsvRefusalsNameFileAndLine) {
  EXPECT_EQ(error_of([] { (void)parse_signal_csv("t,a\n0,1\n0.001,x\n", "a.csv"); }),
            "a.csv:3: expected a row `time_s,acceleration_m_s2` of two numbers");
  EXPECT_NE(error_of([] { (void)parse_signal_csv("0,1\n0.001,1\n0.001,1\n", "a.csv"); })
                .find("a.csv:3: time"),
            std::string::npos);
  EXPECT_NE(error_of([] { (void)parse_signal_csv("0,1\n0.001,1\n0.0025,1\n0.003,1\n", "a.csv"); })
                .find("a.csv:3: time step"),
            std::string::npos);
  EXPECT_EQ(error_of([] { (void)parse_signal_csv("t,a\n0,1\n", "a.csv"); }),
            "a.csv:2: fewer than 2 rows of `time_s,acceleration_m_s2`");
  EXPECT_EQ(error_of([] { (void)read_signal_file("/dev/zero.wav", 0); }),
            "/dev/zero.wav: no such file (expected a signal (WAV))");
  EXPECT_EQ(error_of([] { (void)read_signal_file("rec.flac", 0); }),
            "rec.flac: a recorded signal is a .wav or a .csv file");
}

}  // namespace
}  // namespace lathectl::io
