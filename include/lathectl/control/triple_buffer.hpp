#pragma once
// Lock-free hand-over of a value from one thread to another (one writer, one reader): three
// slots, one the writer fills, one the reader holds, one in the middle exchanged atomically.
// Neither side ever waits or allocates; the reader sees the newest complete value (older ones
// written meanwhile are skipped). Used to move the modulated-feed re-plan out of the servo thread
// (ModulationPlanner).

#include <atomic>

namespace lathectl::control {

template <class T>
class TripleBuffer {
 public:
  // Writer: fill back(), then publish() it.
  [[nodiscard]] T& back() noexcept { return slots_[back_]; }
  void publish() noexcept {
    back_ = mid_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndex;
  }
  // Reader: fetch() takes the newest published value into front() (false: none since the last).
  [[nodiscard]] bool fetch() noexcept {
    if ((mid_.load(std::memory_order_acquire) & kFresh) == 0) return false;
    front_ = mid_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  [[nodiscard]] const T& front() const noexcept { return slots_[front_]; }

 private:
  static constexpr unsigned kIndex = 3, kFresh = 4;
  T slots_[3]{};
  unsigned back_ = 0, front_ = 1;
  std::atomic<unsigned> mid_{2};
};

}  // namespace lathectl::control
