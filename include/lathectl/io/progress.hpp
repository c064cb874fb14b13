#pragma once
// Progress of a long command (run, demo, lobes) on stderr, with an estimate of the time left.
// On a terminal: one line rewritten with '\r' (what, percent, detail, elapsed, time left), ended
// with a newline. When stderr is a pipe or a log: a plain line every kPlainInterval, the first
// only once that much time has passed, so a short command prints nothing and a long one shows in
// a log that it is alive and how far it is.

#include <chrono>
#include <functional>
#include <mutex>
#include <string>

namespace lathectl::io {

class Progress {
 public:
  // Silent: followed (the simulations step one at a time and call the poll) but never drawn.
  enum class Mode { Auto, Terminal, Plain, Off, Silent };
  // Seconds between two plain lines (and before the first).
  static constexpr double kPlainInterval = 10.0;

  // Auto: Terminal when stderr is a terminal, else Plain.
  explicit Progress(std::string what, Mode mode = Mode::Auto);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Fraction done in [0, 1] and an optional detail ("3 of 27"). Thread-safe; redraws a terminal
  // line at most every 0.2 s (and always at 1).
  void update(double fraction, const std::string& detail = "");
  // Clears the line so that other output can be printed, then redraws it (thread-safe).
  template <class F>
  void print_above(F&& print) {
    std::lock_guard lock(mutex_);
    clear_locked();
    print();
    if (mode_ == Mode::Terminal) draw_locked();  // a plain line waits for its interval
  }
  // Called by every update() before anything is drawn, on the updating thread, outside the
  // lock; it may throw to stop the work (the Python module: Ctrl-C → KeyboardInterrupt).
  void set_poll(std::function<void()> poll) { poll_ = std::move(poll); }
  // The poll alone (work that has no fraction to show, e.g. one part of many).
  void poll() {
    if (poll_) poll_();
  }
  // Ends the line with a newline (once; also done by the destructor).
  void finish();

  [[nodiscard]] bool enabled() const { return mode_ != Mode::Off; }
  // The line as it would be drawn now, e.g. "lobes: 42 % (3 of 7), 12 s, about 17 s left"
  // (for tests). The time left is elapsed·(1 − f)/f, given once 2 % and 2 s are done.
  [[nodiscard]] std::string text(double elapsed_s) const;

  static bool stderr_is_terminal();

 private:
  void clear_locked();
  void draw_locked();

  std::string what_, detail_;
  double fraction_ = 0.0;
  Mode mode_;
  bool drawn_ = false, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_;
  std::mutex mutex_;
  std::function<void()> poll_;
};

// The progress line the simulations of this thread report to while the scope lives (`run`:
// configure_and_run updates it with the simulated time of each rig that steps one at a time).
class ProgressScope {
 public:
  explicit ProgressScope(Progress& p);
  ~ProgressScope();
  ProgressScope(const ProgressScope&) = delete;
  ProgressScope& operator=(const ProgressScope&) = delete;
  [[nodiscard]] static Progress* current();
  // The current progress line's poll, if this thread has one (a long loop's chance to stop).
  static void poll() {
    if (Progress* p = current()) p->poll();
  }
  // Numbers the simulations of the scope: 1, 2, ...
  static int next_simulation();
};

}  // namespace lathectl::io
