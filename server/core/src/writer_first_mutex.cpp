#include "writer_first_mutex.hpp"

#include <algorithm>
#include <cerrno>
#include <system_error>
#include <utility>
#include <vector>

namespace semfuse::server {
namespace {

void check(int error, const char* what) {
  if (error != 0) throw std::system_error(error, std::generic_category(), what);
}

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

WriterFirstMutex::WriterFirstMutex() {
  pthread_rwlockattr_t attributes;
  check(pthread_rwlockattr_init(&attributes), "pthread_rwlockattr_init");
#ifdef __GLIBC__
  // The only kind under which a waiting writer blocks new readers (glibc's default prefers them).
  check(pthread_rwlockattr_setkind_np(&attributes, PTHREAD_RWLOCK_PREFER_WRITER_NONRECURSIVE_NP),
        "pthread_rwlockattr_setkind_np");
#endif
  const int error = pthread_rwlock_init(&lock_, &attributes);
  pthread_rwlockattr_destroy(&attributes);
  check(error, "pthread_rwlock_init");
}

WriterFirstMutex::~WriterFirstMutex() { pthread_rwlock_destroy(&lock_); }

void WriterFirstMutex::lock() { check(pthread_rwlock_wrlock(&lock_), "pthread_rwlock_wrlock"); }
bool WriterFirstMutex::try_lock() { return pthread_rwlock_trywrlock(&lock_) == 0; }
void WriterFirstMutex::unlock() { pthread_rwlock_unlock(&lock_); }

void WriterFirstMutex::lock_shared() {
  if (int* count = heldShared(this)) {
    ++*count;
    return;
  }
  int error;
  // EAGAIN: the maximum number of readers; another one leaves soon.
  while ((error = pthread_rwlock_rdlock(&lock_)) == EAGAIN) {
  }
  check(error, "pthread_rwlock_rdlock");
  sharedHolds().emplace_back(this, 1);
}

bool WriterFirstMutex::try_lock_shared() {
  if (int* count = heldShared(this)) {
    ++*count;
    return true;
  }
  if (pthread_rwlock_tryrdlock(&lock_) != 0) return false;
  sharedHolds().emplace_back(this, 1);
  return true;
}

void WriterFirstMutex::unlock_shared() {
  const auto it = findHold(this);
  if (it == sharedHolds().end()) return;  // not held by this thread: nothing of ours to release
  if (--it->second > 0) return;
  sharedHolds().erase(it);
  pthread_rwlock_unlock(&lock_);
}

}  // namespace semfuse::server
