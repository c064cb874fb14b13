#include "vibsensor_source.hpp"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "lathectl/io/signal_file.hpp"

namespace lathectl::hal {

namespace {

constexpr double kClip = 0.999;

class AlsaSource : public Source {
 public:
  explicit AlsaSource(const SourceOptions& o) : o_(o) {
    format_ = o.format == "S16_LE"     ? SND_PCM_FORMAT_S16_LE
              : o.format == "S32_LE"   ? SND_PCM_FORMAT_S32_LE
              : o.format == "FLOAT_LE" ? SND_PCM_FORMAT_FLOAT_LE
                                       : SND_PCM_FORMAT_UNKNOWN;
    if (format_ == SND_PCM_FORMAT_UNKNOWN)
      throw std::runtime_error("--format " + o.format + ": expected S16_LE, S32_LE or FLOAT_LE");
    channels_ = o.channels > 0 ? o.channels : o.channel + 1;
    if (o.channel < 0 || o.channel >= channels_)
      throw std::runtime_error("--channel " + std::to_string(o.channel) + " of " +
                               std::to_string(channels_) + " channels (counted from 0)");
    check(snd_pcm_open(&pcm_, o.device.c_str(), SND_PCM_STREAM_CAPTURE, 0), "open");
    // Interleaved reads at the device's own rate (no resampling), about 0.1 s of buffer.
    check(snd_pcm_set_params(pcm_, format_, SND_PCM_ACCESS_RW_INTERLEAVED,
                             static_cast<unsigned>(channels_), o.rate_Hz, 0, 100000),
          "set " + o.format + ", " + std::to_string(channels_) + " channels, " +
              std::to_string(o.rate_Hz) + " Hz");
    width_ = static_cast<std::size_t>(snd_pcm_format_physical_width(format_) / 8);
    scale_ = o.full_scale_V / o.sensitivity_V_per_m_s2;
  }
  ~AlsaSource() override {
    if (pcm_ != nullptr) snd_pcm_close(pcm_);
  }
  AlsaSource(const AlsaSource&) = delete;
  AlsaSource& operator=(const AlsaSource&) = delete;

  std::size_t read(std::vector<double>& out) override {
    const std::size_t frame = width_ * static_cast<std::size_t>(channels_);
    raw_.resize(out.size() * frame);
    snd_pcm_sframes_t n = 0;
    for (;;) {
      n = snd_pcm_readi(pcm_, raw_.data(), out.size());
      if (n >= 0) break;
      if (n == -EPIPE || n == -ESTRPIPE || n == -EINTR) {
        if (n == -EPIPE) ++overruns_;
        check(snd_pcm_recover(pcm_, static_cast<int>(n), 1), "recover");
        continue;
      }
      check(static_cast<int>(n), "read");
    }
    const auto frames = static_cast<std::size_t>(n);
    for (std::size_t k = 0; k < frames; ++k) {
      const double v = sample(raw_.data() + k * frame + width_ * static_cast<std::size_t>(o_.channel));
      if (std::abs(v) >= kClip) ++clipped_;
      out[k] = v * scale_;
    }
    return frames;
  }
  [[nodiscard]] double rate_Hz() const override { return o_.rate_Hz; }
  [[nodiscard]] unsigned long overruns() const override { return overruns_; }

 private:
  void check(int rc, const std::string& what) const {
    if (rc < 0)
      throw std::runtime_error("ALSA device " + o_.device + ": " + what + ": " + snd_strerror(rc));
  }
  [[nodiscard]] double sample(const unsigned char* p) const noexcept {
    if (format_ == SND_PCM_FORMAT_S16_LE) {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v / 32768.0;
    }
    if (format_ == SND_PCM_FORMAT_S32_LE) {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v / 2147483648.0;
    }
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  SourceOptions o_;
  snd_pcm_t* pcm_ = nullptr;
  snd_pcm_format_t format_ = SND_PCM_FORMAT_UNKNOWN;
  int channels_ = 1;
  std::size_t width_ = 4;
  double scale_ = 1.0;
  std::vector<unsigned char> raw_;
  unsigned long overruns_ = 0;
};

class FileSource : public Source {
 public:
  explicit FileSource(const SourceOptions& o) : signal_(io::read_signal_file(o.file, o.channel)) {
    const bool scaled = signal_.unit == io::Signal::Unit::full_scale;
    scale_ = scaled ? o.full_scale_V / o.sensitivity_V_per_m_s2 : 1.0;
    if (scaled)
      for (double v : signal_.samples)
        if (std::abs(v) >= kClip) ++clipped_;
  }
  std::size_t read(std::vector<double>& out) override {
    std::size_t k = 0;
    for (; k < out.size() && at_ < signal_.samples.size(); ++k) out[k] = signal_.samples[at_++] * scale_;
    return k;
  }
  [[nodiscard]] double rate_Hz() const override { return signal_.rate_Hz; }

 private:
  io::Signal signal_;
  double scale_ = 1.0;
  std::size_t at_ = 0;
};

}  // namespace

std::unique_ptr<Source> open_source(const SourceOptions& o) {
  if (o.device.empty() == o.file.empty())
    throw std::runtime_error("give one of --device NAME and --file F.wav|F.csv");
  const bool csv = o.file.size() >= 4 && (o.file.substr(o.file.size() - 4) == ".csv" ||
                                          o.file.substr(o.file.size() - 4) == ".CSV");
  if (!csv && !(o.sensitivity_V_per_m_s2 > 0.0 && std::isfinite(o.sensitivity_V_per_m_s2)))
    throw std::runtime_error("--sensitivity V_per_m_s2 (> 0) is required with --device or a WAV");
  if (!(o.full_scale_V > 0.0 && std::isfinite(o.full_scale_V)))
    throw std::runtime_error("--full-scale V must be > 0");
  if (!o.file.empty()) return std::make_unique<FileSource>(o);
  return std::make_unique<AlsaSource>(o);
}

}  // namespace lathectl::hal
