#pragma once
// The map's shared mutex: a writer that waits is let in before new readers. glibc's rwlock, under
// std::shared_mutex, prefers readers: while queries keep overlapping shared holds (raycast copies,
// the live mesh's batches, the distance field's copies, snapshots), the fusion thread waiting to
// write a frame is passed over again and again, and with enough queries it never writes. Here a
// writer that waits stops new readers; it gets the map once those already reading are done.
//
// A thread that already holds it shared may take it shared again (counted per thread, without
// waiting: queuing behind the writer would wait for itself). Taking it exclusively while holding
// it, or shared while holding it exclusively, deadlocks as with any shared mutex. Meets the
// SharedMutex requirements, for std::unique_lock and std::shared_lock; a shared hold is released by
// the thread that took it.
#include <pthread.h>

namespace semfuse::server {

class WriterFirstMutex {
 public:
  WriterFirstMutex();
  ~WriterFirstMutex();
  WriterFirstMutex(const WriterFirstMutex&) = delete;
  WriterFirstMutex& operator=(const WriterFirstMutex&) = delete;

  void lock();
  bool try_lock();
  void unlock();
  void lock_shared();
  bool try_lock_shared();
  void unlock_shared();

 private:
  pthread_rwlock_t lock_;
};

}  // namespace semfuse::server
