#pragma once
// lathectl_vibsensor's signal sources: an ALSA capture device or a recorded file (WAV, CSV), each
// giving blocks of acceleration samples [m/s²] at its rate. A WAV's or a device's sample is a
// fraction of the interface's full scale: acceleration = sample · full_scale_V / sensitivity.

#include <alsa/asoundlib.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace lathectl::hal {

struct SourceOptions {
  std::string device;  // ALSA PCM name (hw:1, plughw:CARD=..., a name from an asoundrc)
  std::string file;    // or a recording (.wav, .csv)
  std::string format = "S32_LE";  // the device's: S16_LE, S32_LE, FLOAT_LE
  unsigned rate_Hz = 48000;       // the device's
  int channels = 0;               // the device's interleaved channels; 0: channel + 1
  int channel = 0;                // the accelerometer's, from 0
  double sensitivity_V_per_m_s2 = 0.0;
  double full_scale_V = 1.0;      // the interface's input at digital full scale
};

class Source {
 public:
  virtual ~Source() = default;
  // Up to out.size() samples into `out` [m/s²]; 0 at the end of a recording. Throws on a device
  // error it cannot recover from.
  virtual std::size_t read(std::vector<double>& out) = 0;
  [[nodiscard]] virtual double rate_Hz() const = 0;
  [[nodiscard]] virtual unsigned long overruns() const { return 0; }
  // Samples at or beyond 99.9 % of full scale so far (the interface clipped).
  [[nodiscard]] unsigned long clipped() const { return clipped_; }

 protected:
  unsigned long clipped_ = 0;
};

// Throws std::runtime_error (a device) or io::InputError (a file) naming what it could not open.
std::unique_ptr<Source> open_source(const SourceOptions& o);

}  // namespace lathectl::hal
