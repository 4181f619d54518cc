#include "writer_first_mutex.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace semfuse::server {
namespace {

// The shared holds of the calling thread: which mutex, how many times (rarely more than one).
std::vector<std::pair<const WriterFirstMutex*, int>>& sharedHolds() {
  thread_local std::vector<std::pair<const WriterFirstMutex*, int>> holds;
  return holds;
}

// The calling thread's hold of `mutex`, or the end of its holds when it holds none.
auto findHold(const WriterFirstMutex* mutex) {
  auto& holds = sharedHolds();
  return std::find_if(holds.begin(), holds.end(), [mutex](const auto& hold) { return hold.first == mutex; });
}

// The calling thread's count for `mutex`, or null when it holds none.
int* heldShared(const WriterFirstMutex* mutex) {
  const auto it = findHold(mutex);
  return it == sharedHolds().end() ? nullptr : &it->second;
}

}  // namespace

void WriterFirstMutex::lock() {
  std::unique_lock state(state_mutex_);
  if (writers_waiting_++ == 0) ahead_slots_ = kAheadPassesPerWait;
  writer_may_enter_.wait(state, [this] { return !writing_ && !admitting_ && readers_ == 0; });
  if (--writers_waiting_ == 0) ahead_slots_ = 0;
  writing_ = true;
}

bool WriterFirstMutex::try_lock() {
  std::lock_guard state(state_mutex_);
  if (writing_ || admitting_ || readers_ > 0) return false;
  writing_ = true;
  return true;
}

void WriterFirstMutex::unlock() {
  {
    std::lock_guard state(state_mutex_);
    writing_ = false;
  }
  // Readers who go ahead may enter now; the writers are woken too and wait for them.
  readers_may_enter_.notify_all();
  writer_may_enter_.notify_all();
}

void WriterFirstMutex::admitReadersAhead() {
  std::unique_lock state(state_mutex_);
  if (readers_ahead_waiting_ == 0) return;
  writing_ = false;
  admitting_ = true;  // keeps other writers out, and (with writers_waiting_) other readers
  ++writers_waiting_;
  const int slots_before = ahead_slots_;
  ahead_slots_ = readers_ahead_waiting_;
  readers_may_enter_.notify_all();
  writer_may_enter_.wait(state, [this] { return (ahead_slots_ == 0 || readers_ahead_waiting_ == 0) && readers_ == 0; });
  --writers_waiting_;
  ahead_slots_ = writers_waiting_ > 0 ? slots_before : 0;
  admitting_ = false;
  writing_ = true;
}

void WriterFirstMutex::lock_shared() { lockShared(false); }
void WriterFirstMutex::lock_shared_ahead() { lockShared(true); }

void WriterFirstMutex::lockShared(bool ahead_of_waiting_writers) {
  if (int* count = heldShared(this)) {
    ++*count;
    return;
  }
  {
    std::unique_lock state(state_mutex_);
    if (ahead_of_waiting_writers) ++readers_ahead_waiting_;
    readers_may_enter_.wait(
        state, [&] { return !writing_ && (writers_waiting_ == 0 || (ahead_of_waiting_writers && ahead_slots_ > 0)); });
    if (ahead_of_waiting_writers) {
      --readers_ahead_waiting_;
      if (writers_waiting_ > 0) --ahead_slots_;
    }
    ++readers_;
  }
  sharedHolds().emplace_back(this, 1);
}

bool WriterFirstMutex::try_lock_shared() {
  if (int* count = heldShared(this)) {
    ++*count;
    return true;
  }
  {
    std::lock_guard state(state_mutex_);
    if (writing_ || writers_waiting_ > 0) return false;
    ++readers_;
  }
  sharedHolds().emplace_back(this, 1);
  return true;
}

void WriterFirstMutex::unlock_shared() {
  const auto it = findHold(this);
  if (it == sharedHolds().end()) return;  // not held by this thread: nothing of ours to release
  if (--it->second > 0) return;
  sharedHolds().erase(it);
  bool last_reader = false;
  {
    std::lock_guard state(state_mutex_);
    last_reader = --readers_ == 0;
  }
  if (last_reader) writer_may_enter_.notify_all();
}

}  // namespace semfuse::server
