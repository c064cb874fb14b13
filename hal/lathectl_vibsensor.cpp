// lathectl_vibsensor — system B's measuring chain on a real accelerometer: a userspace HAL
// component. Seed 001's blocks 16–20 (sensor, amplifier 17 with the dead zone of setter 18,
// amplitude ADC 19, frequency detector 20) are the core's sensors::VibrationChain, fed the
// acceleration through update_acceleration() (its high-pass, two integrations, the chain's own
// high-pass; no simulated noise), configured from the scenario's [vibration_sensor] at the
// signal's own sample rate. Its a0 and ω_d go to the pins lathectl_modfeed's inputs net to, as
// lathectl_chatter's do in the simulated session.
//
//   loadusr -W lathectl_vibsensor --scenario PATH --device NAME --sensitivity V_per_m_s2
//           [--rate 48000] [--format S32_LE] [--channels N] [--channel 0] [--full-scale 1]
//   loadusr -W lathectl_vibsensor --scenario PATH --file F.wav|F.csv [--sensitivity …]
//   lathectl_vibsensor … --print [--frames N]     no HAL: a0 and ω_d at each amplitude gate's end
//
// A device is read as it delivers (blocking interleaved reads of about 10 ms); a recording is
// replayed at its own rate in HAL mode (paced by the clock), as fast as it is read with --print.
// --frames N stops after N frames (ALSA's file plugin neither paces nor ends).
// Pins, options and wiring: lathectl_vibsensor(9), docs/linuxcnc.md.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <numbers>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "lathectl/sensors/vibration_chain.hpp"
#include "lathectl_hal.hpp"
#include "pins/vibsensor.hpp"
#include "systems/b_chatter/settings.hpp"
#include "vibsensor_source.hpp"

namespace {

using lathectl::hal::SourceOptions;
constexpr const char* kName = "lathectl_vibsensor";
constexpr const char* kPrefix = "lathectl-vibsensor";

struct Pins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_VIBSENSOR_PINS)
};

struct Options {
  SourceOptions source;
  std::string scenario;
  long long frames = -1;  // stop after; -1 never
  bool print = false;
};

std::atomic<bool> stop{false};
void on_signal(int) { stop = true; }

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "%s: %s\nusage: lathectl_vibsensor [--scenario PATH] (--device NAME | --file "
               "F.wav|F.csv) [--sensitivity V_per_m_s2] [--full-scale V] [--rate HZ] [--format "
               "S16_LE|S32_LE|FLOAT_LE] [--channels N] [--channel I] [--frames N] [--print]\n",
               kName, why.c_str());
  std::exit(2);
}

double number(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v)) usage(flag + " " + text + ": not a number");
  return v;
}

long long whole(const std::string& flag, const char* text, double lo, double hi) {
  const double v = number(flag, text);
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    usage(flag + " " + text + ": expected a whole number in " + std::to_string(static_cast<long long>(lo)) +
          " … " + std::to_string(static_cast<long long>(hi)));
  return static_cast<long long>(v);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--print") {
      o.print = true;
      continue;
    }
    if (i + 1 >= argc) usage(a + ": expected a value");
    const char* v = argv[++i];
    if (a == "--scenario") o.scenario = v;
    else if (a == "--device") o.source.device = v;
    else if (a == "--file") o.source.file = v;
    else if (a == "--format") o.source.format = v;
    else if (a == "--sensitivity") o.source.sensitivity_V_per_m_s2 = number(a, v);
    else if (a == "--full-scale") o.source.full_scale_V = number(a, v);
    else if (a == "--rate") o.source.rate_Hz = static_cast<unsigned>(whole(a, v, 1000, 768000));
    else if (a == "--channels") o.source.channels = static_cast<int>(whole(a, v, 1, 64));
    else if (a == "--channel") o.source.channel = static_cast<int>(whole(a, v, 0, 63));
    else if (a == "--frames") o.frames = whole(a, v, 1, 1e15);
    else usage("unknown option " + a);
  }
  return o;
}

// The scenario's chain (its defaults without one) at the signal's rate, no simulated noise.
lathectl::sensors::VibrationChain::Params chain_params(const Options& o, double rate_Hz) {
  lathectl::sensors::VibrationChain::Params p =
      lathectl::systems::b_chatter::Settings{}.rig.vibration;
  if (!o.scenario.empty()) {
    const auto sc = lathectl::hal::load_system(o.scenario.c_str(),
                                               lathectl::systems::b_chatter::kReadSection);
    p = sc.get<lathectl::systems::b_chatter::Settings>().rig.vibration;
  }
  p.sample_period_s = 1.0 / rate_Hz;
  p.noise_m = 0.0;
  return p;
}

// The loop: blocks of about 10 ms into the chain; `publish` after each block, `gate` at each
// amplitude gate's end (--print's rows).
template <class Publish, class Gate>
void run(lathectl::hal::Source& src, lathectl::sensors::VibrationChain& chain, const Options& o,
         bool paced, Publish&& publish, Gate&& gate) {
  const double rate = src.rate_Hz();
  std::vector<double> block(static_cast<std::size_t>(std::max(1.0, std::round(rate / 100.0))));
  const auto per_gate =
      std::max(1LL, std::llround(chain.params().amplitude_gate_s * rate));
  long long done = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (!stop && (o.frames < 0 || done < o.frames)) {
    if (o.frames >= 0)
      block.resize(static_cast<std::size_t>(std::min<long long>(
          static_cast<long long>(block.size()), o.frames - done)));
    const std::size_t n = src.read(block);
    if (n == 0) break;
    double peak = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      chain.update_acceleration(block[k]);
      peak = std::max(peak, std::abs(block[k]));
      if (++done % per_gate == 0) gate(static_cast<double>(done) / rate);
    }
    publish(peak, done);
    if (paced)
      std::this_thread::sleep_until(t0 + std::chrono::duration<double>(static_cast<double>(done) / rate));
  }
}

int run_print(lathectl::hal::Source& src, lathectl::sensors::VibrationChain& chain,
              const Options& o) {
  std::printf("time_s,a0_um,omega_d_Hz\n");
  run(src, chain, o, false, [](double, long long) {},
      [&](double t) {
        std::printf("%.6f,%.9g,%.9g\n", t, chain.a0_m() * 1e6,
                    chain.omega_d() / (2.0 * std::numbers::pi));
      });
  std::fprintf(stderr, "%s: %lu overruns, %lu clipped samples\n", kName, src.overruns(),
               src.clipped());
  return 0;
}

int run_hal(lathectl::hal::Source& src, lathectl::sensors::VibrationChain& chain,
            const Options& o) {
  const int comp = hal_init(kName);
  if (comp < 0) {
    std::fprintf(stderr, "%s: hal_init failed (%d): is a HAL session running?\n", kName, comp);
    return 1;
  }
  Pins* pins = nullptr;
  try {
    lathectl::hal::export_pin_block(pins, comp, kPrefix);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    hal_exit(comp);
    return 1;
  }
  Pins& p = *pins;
  hal_ready(comp);
  *p.running = 1;
  int rc = 0;
  try {
    run(src, chain, o, !o.source.file.empty(),
        [&](double peak, long long done) {
          *p.a0_um = chain.a0_m() * 1e6;
          *p.omega_d_Hz = chain.omega_d() / (2.0 * std::numbers::pi);
          *p.vibration_um = chain.sensor_m() * 1e6;
          *p.acceleration = peak;
          *p.frames = static_cast<std::uint32_t>(done);
          *p.overruns = static_cast<std::uint32_t>(src.overruns());
          *p.clipped = static_cast<std::uint32_t>(src.clipped());
        },
        [](double) {});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    rc = 1;
  }
  *p.running = 0;
  while (!stop && rc == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  hal_exit(comp);
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    auto src = lathectl::hal::open_source(o.source);
    lathectl::sensors::VibrationChain chain;
    chain.configure(chain_params(o, src->rate_Hz()));
    return o.print ? run_print(*src, chain, o) : run_hal(*src, chain, o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
}
