// A small least-recently-used map with a fixed capacity (a detail of the public headers, not API):
// the capture service's live sessions and an AvatarBuilder's custom regressors are kept in one so
// that a long-running server's memory stays bounded whatever clients ask for. Not thread-safe:
// the owner holds its own lock.
#pragma once
#include <cstddef>
#include <list>
#include <map>
#include <stdexcept>
#include <utility>

namespace caliper::detail {

template <class Key, class Value>
class LruCache {
 public:
  explicit LruCache(std::size_t capacity) : capacity_(capacity) {
    if (capacity_ == 0) throw std::invalid_argument("LruCache: capacity must be at least 1");
  }

  // The value, now the most recently used; nullptr when absent. Valid until the next insert/erase.
  Value* find(const Key& key) {
    auto it = index_.find(key);
    if (it == index_.end()) return nullptr;
    items_.splice(items_.begin(), items_, it->second);
    return &it->second->second;
  }
  // The value without making it the most recently used (e.g. for a listing); nullptr when absent.
  Value* peek(const Key& key) {
    auto it = index_.find(key);
    return it == index_.end() ? nullptr : &it->second->second;
  }
  bool contains(const Key& key) const { return index_.count(key) != 0; }

  // Inserts or replaces; the least recently used entries beyond the capacity are dropped.
  Value& insert(const Key& key, Value value) {
    if (auto it = index_.find(key); it != index_.end()) {
      it->second->second = std::move(value);
      items_.splice(items_.begin(), items_, it->second);
      return it->second->second;
    }
    items_.emplace_front(key, std::move(value));
    index_[key] = items_.begin();
    while (items_.size() > capacity_) {
      index_.erase(items_.back().first);
      items_.pop_back();
    }
    return items_.front().second;
  }

  bool erase(const Key& key) {
    auto it = index_.find(key);
    if (it == index_.end()) return false;
    items_.erase(it->second);
    index_.erase(it);
    return true;
  }

  std::size_t size() const { return items_.size(); }
  std::size_t capacity() const { return capacity_; }

 private:
  std::size_t capacity_;
  std::list<std::pair<Key, Value>> items_;  // most recently used first
  std::map<Key, typename std::list<std::pair<Key, Value>>::iterator> index_;
};

}  // namespace caliper::detail
