#include "lathectl/io/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lathectl::io {

bool Progress::stderr_is_terminal() { return ::isatty(2) == 1; }

Progress::Progress(std::string what, Mode mode)
    : what_(std::move(what)),
      mode_(mode == Mode::Auto ? (stderr_is_terminal() ? Mode::Terminal : Mode::Plain) : mode),
      start_(std::chrono::steady_clock::now()),
      last_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() { finish(); }

namespace {
// "12 s", "3 min 05 s", "2 h 07 min".
std::string duration_text(double s) {
  char buf[48];
  if (s < 100.0)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600.0)
    std::snprintf(buf, sizeof buf, "%.0f min %02.0f s", std::floor(s / 60.0),
                  std::floor(std::fmod(s, 60.0)));
  else
    std::snprintf(buf, sizeof buf, "%.0f h %02.0f min", std::floor(s / 3600.0),
                  std::floor(std::fmod(s, 3600.0) / 60.0));
  return buf;
}
}  // namespace

std::string Progress::text(double elapsed_s) const {
  const double f = std::clamp(fraction_, 0.0, 1.0);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%3.0f %%", std::floor(100.0 * f));
  std::string s = what_ + ": " + buf;
  if (!detail_.empty()) s += " (" + detail_ + ")";
  s += ", " + duration_text(elapsed_s);
  if (f >= 0.02 && f < 1.0 && elapsed_s >= 2.0)
    s += ", about " + duration_text(elapsed_s * (1.0 - f) / f) + " left";
  return s;
}

void Progress::update(double fraction, const std::string& detail) {
  if (mode_ == Mode::Off) return;
  if (poll_) poll_();
  if (mode_ == Mode::Silent) return;
  std::lock_guard lock(mutex_);
  if (finished_) return;
  fraction_ = fraction;
  detail_ = detail;
  const auto now = std::chrono::steady_clock::now();
  if (mode_ == Mode::Plain) {
    // Plain lines: every kPlainInterval, the first one kPlainInterval after the start.
    const auto interval = std::chrono::duration<double>(kPlainInterval);
    if (now - start_ < interval || (drawn_ && now - last_ < interval)) return;
  } else if (fraction < 1.0 && now - last_ < std::chrono::milliseconds(200)) {
    return;
  }
  last_ = now;
  draw_locked();
}

void Progress::draw_locked() {
  if (mode_ == Mode::Off || mode_ == Mode::Silent || finished_) return;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string s = text(el);
  if (mode_ == Mode::Terminal)
    std::fprintf(stderr, "\r%s\033[K", s.c_str());
  else
    std::fprintf(stderr, "%s\n", s.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::clear_locked() {
  if (mode_ != Mode::Terminal || !drawn_ || finished_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
}

void Progress::finish() {
  if (mode_ == Mode::Off || mode_ == Mode::Silent) return;
  std::lock_guard lock(mutex_);
  if (finished_) return;
  if (drawn_ && mode_ == Mode::Terminal) {
    draw_locked();
    std::fputc('\n', stderr);
    std::fflush(stderr);
  }
  finished_ = true;
}

namespace {
thread_local Progress* g_current = nullptr;
thread_local int g_simulations = 0;
}  // namespace

ProgressScope::ProgressScope(Progress& p) {
  g_current = &p;
  g_simulations = 0;
}
ProgressScope::~ProgressScope() { g_current = nullptr; }
Progress* ProgressScope::current() { return g_current; }
int ProgressScope::next_simulation() { return ++g_simulations; }

}  // namespace lathectl::io
