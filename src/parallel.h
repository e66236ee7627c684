// Internal: runs fn(i) for i in [0, n) on `threads` workers (one of them the calling thread's
// helper), reporting progress from the calling thread. Each index is handled exactly once and
// writes only its own results, so outcomes never depend on scheduling. Returns, per index, the
// message of the exception fn threw (empty when it succeeded).
#pragma once
#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace caliper::detail {

inline std::vector<std::string> parallel_for(int n, int threads, const std::function<void(int)>& fn,
                                             const std::function<void(int, int)>& progress = {}) {
  std::atomic<int> next{0}, done{0};
  std::vector<std::string> errors(static_cast<size_t>(std::max(n, 0)));
  auto worker = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (const std::exception& e) {
        errors[static_cast<size_t>(i)] = e.what();
      }
      ++done;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(worker);
  if (progress) {
    std::thread own(worker);
    while (done.load() < n) {
      progress(done.load(), n);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    own.join();
    progress(n, n);
  } else {
    worker();
  }
  for (auto& t : pool) t.join();
  return errors;
}

}  // namespace caliper::detail
