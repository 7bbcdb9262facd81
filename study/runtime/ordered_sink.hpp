// Releases results in index order although they arrive in completion order.
//
// A study's results come back from the MPI task farm in the order the runs
// finish, which depends on the number of ranks and on timing. Floating-point
// accumulation is not associative, so every accumulation (a streaming band, a
// row-wise file write) must see the results in index order 0, 1, 2, ... for
// the outcome to be bit-identical on any number of ranks. OrderedSink buffers
// the items that arrive early and hands each item to `consume` as soon as all
// lower indices have been consumed or skipped.
//
// Memory: only the out-of-order window is buffered (the items whose index is
// above the lowest one still missing), not the whole study.
//
// Not synchronised: call push() and skip() from one thread (rank 0 calls the
// farm's on_result in its main thread).
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace rover::study {

template <class T>
class OrderedSink {
 public:
  explicit OrderedSink(std::function<void(int index, T&&)> consume, int first_index = 0)
      : consume_(std::move(consume)), next_(first_index) {
    if (!consume_) throw std::invalid_argument("OrderedSink: no consume function");
  }

  // Hands over the item of `index`: consumed now if it is the next one (and
  // then every buffered item that follows without a gap), buffered otherwise.
  // Throws std::invalid_argument for an index already consumed, skipped or
  // buffered. An exception from `consume` propagates; the index it was given
  // counts as released.
  void push(int index, T item) {
    check_new(index, "push");
    if (index != next_) {
      pending_.emplace(index, std::optional<T>(std::move(item)));
      ++buffered_items_;
      return;
    }
    ++next_;
    consume_(index, std::move(item));
    drain();
  }

  // Declares that `index` will never come (e.g. its result was loaded from a
  // checkpoint and accumulated elsewhere): the items after it are not held up.
  void skip(int index) {
    check_new(index, "skip");
    if (index != next_) {
      pending_.emplace(index, std::nullopt);
      return;
    }
    ++next_;
    drain();
  }

  // Items waiting for a lower index (skip marks are not counted).
  std::size_t buffered() const { return buffered_items_; }
  // The lowest index not yet released (consumed or skipped).
  int next_index() const { return next_; }

 private:
  void check_new(int index, const char* operation) const {
    if (index < next_ || pending_.count(index) != 0)
      throw std::invalid_argument("OrderedSink::" + std::string(operation) + ": index " +
                                  std::to_string(index) + " was already pushed or skipped");
  }

  void drain() {
    for (auto it = pending_.begin(); it != pending_.end() && it->first == next_;
         it = pending_.begin()) {
      const int index = it->first;
      std::optional<T> item = std::move(it->second);
      pending_.erase(it);
      ++next_;
      if (item) {
        --buffered_items_;
        consume_(index, std::move(*item));
      }
    }
  }

  std::function<void(int, T&&)> consume_;
  int next_;
  std::map<int, std::optional<T>> pending_;  // index -> item, or nullopt for a skipped index
  std::size_t buffered_items_ = 0;
};

}  // namespace rover::study
