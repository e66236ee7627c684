#include "recent_events.h"

#include <iterator>

namespace caliper::server {

bool RecentEvents::full_locked(const std::string& key, Clock::time_point now) {
  auto it = events_.find(key);
  if (it == events_.end()) return false;
  auto& times = it->second;
  while (!times.empty() && now - times.front() > window_) times.pop_front();
  if (times.empty()) {
    events_.erase(it);
    return false;
  }
  return static_cast<int>(times.size()) >= max_events_;
}

void RecentEvents::record_locked(const std::string& key, Clock::time_point now) {
  if (events_.size() >= max_keys_ && !events_.count(key)) {
    for (auto it = events_.begin(); it != events_.end();)
      it = it->second.empty() || now - it->second.back() > window_ ? events_.erase(it) : std::next(it);
    while (events_.size() >= max_keys_) events_.erase(events_.begin());
  }
  auto& times = events_[key];
  times.push_back(now);
  while (static_cast<int>(times.size()) > max_events_) times.pop_front();  // only the last N matter
}

bool RecentEvents::full(const std::string& key, Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  return full_locked(key, now);
}

void RecentEvents::record(const std::string& key, Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  record_locked(key, now);
}

std::size_t RecentEvents::keys() {
  std::lock_guard<std::mutex> lock(mutex_);
  return events_.size();
}

bool RecentEvents::try_record(const std::string& key, Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (full_locked(key, now)) return false;
  record_locked(key, now);
  return true;
}

}  // namespace caliper::server
