#pragma once
// Undo/redo of whole states (the viewer keeps one pose per edit: a handful of motors, cheap to copy).
// push() records a new current state and forgets the redo branch; undo()/redo() move along the history
// and return whether they did. The history is capped (oldest states dropped).
#include <cstddef>
#include <deque>
#include <utility>

namespace spinmotor::viewer {

template <class State>
class UndoStack {
 public:
  explicit UndoStack(State initial, std::size_t capacity = 256) : capacity_(capacity < 1 ? 1 : capacity) {
    states_.push_back(std::move(initial));
  }
  const State& current() const { return states_[index_]; }
  void push(State s) {
    states_.erase(states_.begin() + index_ + 1, states_.end());
    states_.push_back(std::move(s));
    if (states_.size() > capacity_ + 1) states_.pop_front();
    index_ = states_.size() - 1;
  }
  bool can_undo() const { return index_ > 0; }
  bool can_redo() const { return index_ + 1 < states_.size(); }
  bool undo() { return can_undo() ? (--index_, true) : false; }
  bool redo() { return can_redo() ? (++index_, true) : false; }
  std::size_t size() const { return states_.size(); }

 private:
  std::deque<State> states_;
  std::size_t index_ = 0;
  std::size_t capacity_;
};

}  // namespace spinmotor::viewer
