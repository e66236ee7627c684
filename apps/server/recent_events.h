// "At most N events per key within a time window", for the server's budgets: wrong pairing codes
// per (client, session), sessions created per client and in all. Thread-safe; holds at most
// `max_keys` keys (expired ones are dropped first, then the oldest-keyed), so a flood of new keys
// cannot grow it without bound.
#pragma once
#include <chrono>
#include <cstddef>
#include <deque>
#include <map>
#include <mutex>
#include <string>

namespace caliper::server {

class RecentEvents {
 public:
  using Clock = std::chrono::steady_clock;
  RecentEvents(int max_events, Clock::duration window, std::size_t max_keys)
      : max_events_(max_events), window_(window), max_keys_(max_keys) {}

  // True when `key` has had max_events within the window before `now`.
  bool full(const std::string& key, Clock::time_point now);
  void record(const std::string& key, Clock::time_point now);
  // full() and, when not full, record(), as one step (no race between the two).
  bool try_record(const std::string& key, Clock::time_point now);
  std::size_t keys();

 private:
  bool full_locked(const std::string& key, Clock::time_point now);
  void record_locked(const std::string& key, Clock::time_point now);

  const int max_events_;
  const Clock::duration window_;
  const std::size_t max_keys_;
  std::mutex mutex_;
  std::map<std::string, std::deque<Clock::time_point>> events_;
};

}  // namespace caliper::server
