#include "lathectl/io/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lathectl::io {

bool Progress::stderr_is_terminal() { return ::isatty(2) == 1; }

Progress::Progress(std::string what, bool enabled)
    : what_(std::move(what)),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() { finish(); }

std::string Progress::text(double elapsed_s) const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%3.0f %%", std::floor(100.0 * std::clamp(fraction_, 0.0, 1.0)));
  std::string s = what_ + ": " + buf;
  if (!detail_.empty()) s += " (" + detail_ + ")";
  std::snprintf(buf, sizeof buf, ", %.0f s", elapsed_s);
  return s + buf;
}

void Progress::update(double fraction, const std::string& detail) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  if (finished_) return;
  fraction_ = fraction;
  detail_ = detail;
  const auto now = std::chrono::steady_clock::now();
  if (fraction < 1.0 && now - last_ < std::chrono::milliseconds(200)) return;
  last_ = now;
  draw_locked();
}

void Progress::draw_locked() {
  if (!enabled_ || finished_) return;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string s = text(el);
  std::fprintf(stderr, "\r%s\033[K", s.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::clear_locked() {
  if (!enabled_ || !drawn_ || finished_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  if (finished_) return;
  if (drawn_) {
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
