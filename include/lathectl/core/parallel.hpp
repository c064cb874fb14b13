#pragma once
// The one parallel-for (the host's studies, sweeps and Monte Carlo; the core's stability charts):
// fn(i) for every i in [0, n) on up to `threads` threads (0: the machine's cores), each index
// exactly once. The first exception any fn throws is rethrown here once every thread has joined,
// and the others stop taking new indices: a divergence in one run of a sweep ends as that run's
// one-line error, never in std::terminate. Not for the real-time path (it starts threads).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace lathectl::core {

template <class Fn>
void parallel_for(std::size_t n, Fn&& fn, unsigned threads = 0) {
  if (n == 0) return;
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  const auto workers = static_cast<unsigned>(std::min<std::size_t>(threads, n));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first;
  std::mutex m;
  auto work = [&] {
    for (std::size_t i; !failed.load(std::memory_order_relaxed) && (i = next++) < n;) {
      try {
        fn(i);
      } catch (...) {
        const std::lock_guard lock(m);
        if (!first) first = std::current_exception();
        failed = true;
      }
    }
  };
  if (workers == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(workers - 1);
    for (unsigned t = 1; t < workers; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace lathectl::core
