#pragma once
// Progress of a long command on a terminal: one line on stderr, rewritten with '\r' (what,
// percent, elapsed seconds), ended with a newline. Silent when stderr is not a terminal (CI,
// pipes, files), so logs and test outputs stay as they were.

#include <chrono>
#include <mutex>
#include <string>

namespace lathectl::io {

class Progress {
 public:
  // enabled: draw at all (default: stderr is a terminal).
  explicit Progress(std::string what, bool enabled = stderr_is_terminal());
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Fraction done in [0, 1] and an optional detail ("3 of 27"). Thread-safe; redraws at most
  // every 0.2 s (and always at 1).
  void update(double fraction, const std::string& detail = "");
  // Clears the line so that other output can be printed, then redraws it (thread-safe).
  template <class F>
  void print_above(F&& print) {
    std::lock_guard lock(mutex_);
    clear_locked();
    print();
    draw_locked();
  }
  // Ends the line with a newline (once; also done by the destructor).
  void finish();

  [[nodiscard]] bool enabled() const { return enabled_; }
  // The line as it would be drawn now, e.g. "lobes: 42 % (3 of 7), 12 s" (for tests).
  [[nodiscard]] std::string text(double elapsed_s) const;

  static bool stderr_is_terminal();

 private:
  void clear_locked();
  void draw_locked();

  std::string what_, detail_;
  double fraction_ = 0.0;
  bool enabled_, drawn_ = false, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_;
  std::mutex mutex_;
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
  // Numbers the simulations of the scope: 1, 2, ...
  static int next_simulation();
};

}  // namespace lathectl::io
