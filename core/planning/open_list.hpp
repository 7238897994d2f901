#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace strata {

/// The frontier of a grid search: a binary min-heap of (key, tie, slot) in one flat vector, so pushing and
/// popping never allocate once it has grown. Stale entries are not removed (no decrease-key): the search
/// skips a slot it has already closed, which is cheaper than tracking heap positions.
class OpenList {
 public:
  struct Entry {
    double key = 0.0;  ///< ordering value (g for Dijkstra, f = g + h for A*)
    double tie = 0.0;  ///< smaller first among equal keys (A* uses -g: deeper nodes first)
    int slot = 0;
  };

  void reserve(std::size_t n) { heap_.reserve(n); }
  [[nodiscard]] bool empty() const { return heap_.empty(); }
  void clear() { heap_.clear(); }  ///< keeps the storage
  void push(double key, double tie, int slot) {
    heap_.push_back({key, tie, slot});
    std::push_heap(heap_.begin(), heap_.end(), later);
  }
  Entry pop() {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const Entry top = heap_.back();
    heap_.pop_back();
    return top;
  }

 private:
  static bool later(const Entry& a, const Entry& b) {
    return a.key > b.key || (a.key == b.key && a.tie > b.tie);
  }
  std::vector<Entry> heap_;
};

}  // namespace strata
