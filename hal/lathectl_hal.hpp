#pragma once
// What every lathectl HAL component shares: the RTAPI/HAL C headers, pin and parameter export
// that throws on failure (so rtapi_app_main has one error path), module-parameter parsing, the
// system-E scenario loader, and the update-time meter.
//
// A component is one .cpp in hal/ plus one line in hal/CMakeLists.txt. Its rtapi_app_main
// configures everything (reads files, allocates, may throw — caught there, reported with
// rtapi_print_msg, and the load fails); its realtime function never allocates, throws or logs.

extern "C" {
#include <hal.h>
#include <rtapi.h>
#ifdef RTAPI  // a realtime module's; a userspace component (ULAPI, lathectl_vibsensor) has none
#include <rtapi_app.h>
#endif
}

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "pins/meter.hpp"

namespace lathectl::hal {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline void check(int rc, const std::string& what) {
  if (rc < 0) throw Error(what + " failed (" + std::to_string(rc) + ")");
}

// Pins: `prefix.name`. Storage for the pointers must come from hal_malloc().
inline void pin(hal_float_t** p, hal_pin_dir_t dir, int comp, const char* prefix,
                const char* name) {
  check(hal_pin_float_newf(dir, p, comp, "%s.%s", prefix, name), std::string("pin ") + name);
  **p = 0.0;
}
inline void pin(hal_bit_t** p, hal_pin_dir_t dir, int comp, const char* prefix, const char* name) {
  check(hal_pin_bit_newf(dir, p, comp, "%s.%s", prefix, name), std::string("pin ") + name);
  **p = 0;
}
inline void pin(hal_s32_t** p, hal_pin_dir_t dir, int comp, const char* prefix, const char* name) {
  check(hal_pin_s32_newf(dir, p, comp, "%s.%s", prefix, name), std::string("pin ") + name);
  **p = 0;
}
inline void pin(hal_u32_t** p, hal_pin_dir_t dir, int comp, const char* prefix, const char* name) {
  check(hal_pin_u32_newf(dir, p, comp, "%s.%s", prefix, name), std::string("pin ") + name);
  **p = 0;
}
inline void param(hal_float_t* p, hal_param_dir_t dir, int comp, const char* prefix,
                  const char* name, double value) {
  check(hal_param_float_newf(dir, p, comp, "%s.%s", prefix, name),
        std::string("parameter ") + name);
  *p = value;
}

// A component's pins and parameters, `prefix.name`, with the component and the prefix bound once.
class Exporter {
 public:
  Exporter(int comp, const char* prefix) noexcept : comp_(comp), prefix_(prefix) {}
  template <class T>
  void in(T** p, const char* name) const {
    pin(p, HAL_IN, comp_, prefix_, name);
  }
  template <class T>
  void out(T** p, const char* name) const {
    pin(p, HAL_OUT, comp_, prefix_, name);
  }
  template <class T>
  void io(T** p, const char* name) const {
    pin(p, HAL_IO, comp_, prefix_, name);
  }
  // A read-only parameter: a value the component was configured with, for halcmd to show.
  void constant(hal_float_t* p, const char* name, double value) const {
    param(p, HAL_RO, comp_, prefix_, name, value);
  }
  [[nodiscard]] int comp() const noexcept { return comp_; }
  [[nodiscard]] const char* prefix() const noexcept { return prefix_; }

 private:
  int comp_;
  const char* prefix_;
};

// The component's pin block, in HAL's shared memory (pins must live there).
template <class Pins>
Pins* allocate_pins() {
  auto* p = static_cast<Pins*>(hal_malloc(sizeof(Pins)));
  if (p == nullptr) throw Error("hal_malloc failed");
  return p;
}

// The pin block in HAL's shared memory (into `pins`), its table's pins and, if it has a meter,
// the meter's exported as `prefix.name`.
template <class Pins>
Pins& export_pin_block(Pins*& pins, int comp_id, const char* prefix) {
  pins = allocate_pins<Pins>();
  const Exporter x(comp_id, prefix);
  pins->export_pins(x);
  if constexpr (requires { pins->meter.export_to(x); }) pins->meter.export_to(x);
  return *pins;
}

#ifdef RTAPI
// The realtime function `prefix` (uses floating point, not reentrant).
inline void export_update(const char* prefix, void (*fn)(void*, long), int comp_id) {
  check(hal_export_funct(prefix, fn, nullptr, 1, 0, comp_id), "hal_export_funct");
}
#endif

// A module parameter holding a number (RTAPI has no floating-point module parameters).
inline double number_param(const char* text, const char* key, double fallback) {
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || errno != 0 || !std::isfinite(v))
    throw Error(std::string("module parameter ") + key + "=" + text + ": expected a number");
  return v;
}

// A module parameter holding a whole number within [lo, hi] (a thread's period in ns, ...);
// `fallback` when unset.
inline long ranged_param(const char* text, const char* key, double fallback, double lo, double hi,
                         const char* range) {
  const double v = number_param(text, key, fallback);
  if (!(v >= lo && v <= hi))
    throw Error(std::string("module parameter ") + key + ": expected " + range);
  return std::lround(v);
}

// A module parameter holding a number that has no default; `what` says what it is.
inline double required_param(const char* text, const char* key, const char* what) {
  if (text == nullptr || *text == '\0')
    throw Error(std::string("module parameter ") + key + "=X (" + what + ") is required");
  return number_param(text, key, 0.0);
}

// The uid the realtime side opens files as. rtapi_app is setuid root and keeps its real and
// effective uid 0; only its filesystem uid is the calling user's (or RTAPI_UID's when LinuxCNC was
// started by root), so access(2) would answer for root: read the fsuid (4th Uid field) instead.
inline long file_uid() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return -1;
  char line[256];
  long uid[4] = {-1, -1, -1, -1};
  while (std::fgets(line, sizeof line, f) != nullptr)
    if (std::sscanf(line, "Uid: %ld %ld %ld %ld", &uid[0], &uid[1], &uid[2], &uid[3]) == 4) break;
  std::fclose(f);
  return uid[3];
}

// Fails with one line naming the file, what it is for and why the realtime side cannot read it.
// A file under a home directory only its owner may enter (Debian's 0700 homes) is unreadable when
// LinuxCNC runs as root, because rtapi then reads files as RTAPI_UID (e.g. 65534, nobody).
inline void require_readable(const std::string& path, const char* what) {
  std::FILE* f = std::fopen(path.c_str(), "r");
  if (f != nullptr) {
    std::fclose(f);
    return;
  }
  const int err = errno;
  std::string msg = std::string("cannot read ") + what + " " + path + ": " + std::strerror(err);
  if (err == EACCES)
    msg += " (the realtime side reads files as uid " + std::to_string(file_uid()) +
           "; make the file readable to that user, or stage a copy with lathectl-rt-stage)";
  throw Error(msg);
}

// The scenario named by the `scenario=` module parameter, read with only `section`'s reader (a
// component links its own system's settings library, not every system's); errors name file,
// line and key. The file's `system` is checked first, so another system's scenario is named as
// such.
inline io::Scenario load_system(const char* path, const io::Section& section) {
  const std::string system(section.system);
  if (path == nullptr || *path == '\0')
    throw Error("module parameter scenario=PATH (a system-" + system +
                " scenario file) is required");
  require_readable(path, "scenario");
  const std::string materials = io::data_dir() + "/materials.toml";
  require_readable(materials, "material library");
  const auto lib = io::MaterialLibrary::load(materials);
  const std::string text = io::read_scenario_text(path);
  {
    const auto doc = io::TomlDocument::parse(text, path);
    io::TableReader root(doc.root(), path, "");
    const std::string found = root.has("system") ? root.string("system") : system;
    if (found != system)
      throw Error(std::string(path) + ": system = \"" + found +
                  "\", this component needs a system-" + system + " scenario");
  }
  return io::parse_scenario(text, path, lib, section);
}

// Wall time of one call with the monotonic clock; the worst case since load (or reset).
// "Homed" as a plant or a stock model may trust it: motion.is-all-homed counts only the joints
// milltask has activated (homing.c, base_get_allhomed), so it reads TRUE from the first servo
// period until milltask configures the joints — while they read X0 Z0, where the simulated plant
// cut a groove as wide as its nose into the bar before anything was homed. A TRUE counts once the
// pin has been FALSE, or once the position has moved while it was TRUE (a halrun session or a
// machine that holds the pin TRUE from the start: positions that never moved are still the
// start-up's).
class HomedGate {
 public:
  bool operator()(bool homed, double x, double z) noexcept {
    if (!homed) {
      open_ = true;
    } else if (!open_) {
      if (!seen_) {
        x0_ = x;
        z0_ = z;
        seen_ = true;
      } else if (x != x0_ || z != z0_) {
        open_ = true;
      }
    }
    return homed && open_;
  }

 private:
  bool open_ = false;
  bool seen_ = false;
  double x0_ = 0.0;
  double z0_ = 0.0;
};

class UpdateTimer {
 public:
  void start() noexcept { t0_ = std::chrono::steady_clock::now(); }
  std::int32_t stop() noexcept {
    const auto ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0_)
            .count();
    last_ = static_cast<std::int32_t>(std::min<long long>(ns, INT32_MAX));
    if (last_ > max_) max_ = last_;
    return last_;
  }
  [[nodiscard]] std::int32_t max() const noexcept { return max_; }
  void reset() noexcept { max_ = 0; }

 private:
  std::chrono::steady_clock::time_point t0_{};
  std::int32_t last_ = 0;
  std::int32_t max_ = 0;
};

// A pin table (hal/pins/<component>.hpp, an X-macro of PIN(member, type, dir, count, unit, doc)
// rows and HEAD(text) headings) made into a pin block's members and its export: the pin's name
// is the member's with '_' → '-', so the two cannot differ; count n > 0 makes the member an array
// of pins name-0 … name-(n-1). lathectl_hal_pin_docs makes the man page's PINS section from it.
enum class PinDir { in, out, io };
// The table's type column as a tag (hal_float_t itself is no template argument: real_t's
// alignment attribute would be dropped).
struct pin_bit {
  using ptr = hal_bit_t*;
};
struct pin_float {
  using ptr = hal_float_t*;
};
struct pin_s32 {
  using ptr = hal_s32_t*;
};
struct pin_u32 {
  using ptr = hal_u32_t*;
};
template <class Kind, int N>
struct PinSlot {
  using type = typename Kind::ptr[N];
};
template <class Kind>
struct PinSlot<Kind, 0> {
  using type = typename Kind::ptr;
};
inline std::string pin_name(const char* member) {
  std::string name(member);
  for (char& c : name)
    if (c == '_') c = '-';
  return name;
}
constexpr hal_pin_dir_t hal_dir(PinDir d) noexcept {
  return d == PinDir::in ? HAL_IN : d == PinDir::out ? HAL_OUT : HAL_IO;
}
template <class T>
void export_pin(const Exporter& x, T*& p, PinDir d, const char* member) {
  pin(&p, hal_dir(d), x.comp(), x.prefix(), pin_name(member).c_str());
}
template <class T, std::size_t N>
void export_pin(const Exporter& x, T* (&p)[N], PinDir d, const char* member) {
  for (std::size_t i = 0; i < N; ++i)
    pin(&p[i], hal_dir(d), x.comp(), x.prefix(),
        (pin_name(member) + "-" + std::to_string(i)).c_str());
}

// The table's field column: a pin copied to or from the machine object's value (read_pins and
// write_pins, generated by LATHECTL_HAL_PIN_BLOCK), or `glue` (the component's own code).
struct Glue {};
template <class Pin, class F>
void read_one(Pin* pin, F& field) noexcept {
  if constexpr (std::is_enum_v<F>)
    field = static_cast<F>(*pin);
  else
    field = *pin;  // the implicit conversion: -Wconversion sees a narrowing one
}
template <class Pin, class F>
void write_one(Pin* pin, const F& field) noexcept {
  if constexpr (std::is_enum_v<F>)
    *pin = static_cast<std::remove_cvref_t<decltype(*pin)>>(field);
  else
    *pin = field;
}
// `slot` is the pin block's member: a pin's pointer, or an array of them (count > 0).
template <PinDir D, class Slot, class F>
void read_pin(const Slot& slot, F& field) noexcept {
  if constexpr (D == PinDir::in && !std::is_same_v<std::remove_cv_t<F>, Glue>) {
    if constexpr (std::is_array_v<Slot>)
      for (std::size_t i = 0; i < std::extent_v<Slot>; ++i) read_one(slot[i], field[i]);
    else
      read_one(slot, field);
  }
}
template <PinDir D, class Slot, class F>
void write_pin(const Slot& slot, const F& field) noexcept {
  if constexpr (D == PinDir::out && !std::is_same_v<F, Glue>) {
    if constexpr (std::is_array_v<Slot>)
      for (std::size_t i = 0; i < std::extent_v<Slot>; ++i) write_one(slot[i], field[i]);
    else
      write_one(slot, field);
  }
}

}  // namespace lathectl::hal

#define LATHECTL_HAL_PIN_MEMBER(m, t, d, n, u, f, doc) \
  ::lathectl::hal::PinSlot<::lathectl::hal::pin_##t, n>::type m;
#define LATHECTL_HAL_PIN_EXPORT(m, t, d, n, u, f, doc) \
  ::lathectl::hal::export_pin(x_, m, ::lathectl::hal::PinDir::d, #m);
#define LATHECTL_HAL_PIN_READ(m, t, d, n, u, f, doc) \
  ::lathectl::hal::read_pin<::lathectl::hal::PinDir::d>(m, f);
#define LATHECTL_HAL_PIN_WRITE(m, t, d, n, u, f, doc) \
  ::lathectl::hal::write_pin<::lathectl::hal::PinDir::d>(m, f);
#define LATHECTL_HAL_NO_HEAD(text)
#define LATHECTL_HAL_PARAM_MEMBER(m, u, f, doc) hal_float_t m;
#define LATHECTL_HAL_PARAM_EXPORT(m, u, f, doc) \
  x_.constant(&m, ::lathectl::hal::pin_name(#m).c_str(), f);
// Inside a pin block struct: a parameter table's members (read-only float parameters, rows
// PARAM(member, unit, field, doc), named as pins are) and export_params(exporter, params), which
// exports each with its field, an expression of the machine's Params `params`.
#define LATHECTL_HAL_PARAM_BLOCK(LIST)                                            \
  LIST(LATHECTL_HAL_PARAM_MEMBER)                                                 \
  template <class Params>                                                         \
  void export_params(const ::lathectl::hal::Exporter& x_, const Params& params) { \
    LIST(LATHECTL_HAL_PARAM_EXPORT)                                               \
  }
// Inside a pin block struct: the table's members, export_pins(exporter), and the copies of the
// pins whose field is the machine's: read_pins(in, out) sets the in pins' fields of `in` (the
// machine's Input), write_pins(in, out) the out pins from `out` (its Output). Both take both, as
// every row's field names one of them.
#define LATHECTL_HAL_PIN_BLOCK(LIST)                                        \
  LIST(LATHECTL_HAL_PIN_MEMBER, LATHECTL_HAL_NO_HEAD)                       \
  void export_pins(const ::lathectl::hal::Exporter& x_) {                   \
    LIST(LATHECTL_HAL_PIN_EXPORT, LATHECTL_HAL_NO_HEAD)                     \
  }                                                                         \
  template <class In, class Out>                                            \
  void read_pins(In& in, [[maybe_unused]] const Out& out) const noexcept {  \
    [[maybe_unused]] const ::lathectl::hal::Glue glue;                      \
    LIST(LATHECTL_HAL_PIN_READ, LATHECTL_HAL_NO_HEAD)                       \
  }                                                                         \
  template <class In, class Out>                                            \
  void write_pins([[maybe_unused]] const In& in, const Out& out) noexcept { \
    [[maybe_unused]] const ::lathectl::hal::Glue glue;                      \
    LIST(LATHECTL_HAL_PIN_WRITE, LATHECTL_HAL_NO_HEAD)                      \
  }

namespace lathectl::hal {

// What every realtime function reports of itself, in its pin block (hal/pins/meter.hpp).
struct MeterPins {
  LATHECTL_HAL_PIN_BLOCK(LATHECTL_METER_PINS)
  void export_to(const Exporter& x) { export_pins(x); }
};

// The meter of one realtime function: begin() at its start, end() at its end; begin() false
// means the thread's period is not `expected` (period-error set, the time written): return.
class Meter {
 public:
  bool begin(MeterPins& p, long period, long expected) noexcept {
    timer_.start();
    if (period == expected) return true;
    *p.period_error = 1;
    *p.update_ns = timer_.stop();
    return false;
  }
  void end(MeterPins& p) noexcept {
    *p.update_ns = timer_.stop();
    *p.update_ns_max = timer_.max();
  }
  // A call that ends early on purpose (a period the function skips): the time only.
  void skip(MeterPins& p) noexcept { *p.update_ns = timer_.stop(); }
  UpdateTimer& timer() noexcept { return timer_; }

 private:
  UpdateTimer timer_;
};

// rtapi_app_main's body: run `setup`, report any exception as one line, fail the load.
template <class Setup>
int guarded_load(const char* comp_name, int comp_id, Setup&& setup) noexcept {
  try {
    setup();
  } catch (const std::exception& e) {
    rtapi_print_msg(RTAPI_MSG_ERR, "%s: %s\n", comp_name, e.what());
    hal_exit(comp_id);
    return -EINVAL;
  } catch (...) {
    rtapi_print_msg(RTAPI_MSG_ERR, "%s: unknown error while loading\n", comp_name);
    hal_exit(comp_id);
    return -EINVAL;
  }
  hal_ready(comp_id);
  return 0;
}

// The whole of rtapi_app_main: the component `name` initialised (its id in `comp_id`), then
// guarded_load.
template <class Setup>
int load_component(const char* name, int& comp_id, Setup&& setup) noexcept {
  comp_id = hal_init(name);
  if (comp_id < 0) return comp_id;
  return guarded_load(name, comp_id, std::forward<Setup>(setup));
}

}  // namespace lathectl::hal

// A module parameter holding a string (a path, or a number read with number_param): one line.
#define LATHECTL_HAL_PARAM(name, doc) \
  static char* name = nullptr;        \
  RTAPI_MP_STRING(name, doc)
