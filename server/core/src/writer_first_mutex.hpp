#pragma once
// The map's shared mutex: a writer that waits is let in before new readers, except readers who
// ask to go first. glibc's rwlock, under std::shared_mutex, prefers readers: while queries keep
// overlapping shared holds (raycast copies, the live mesh's batches, the distance field's copies,
// snapshots), the fusion thread waiting to write a frame is passed over again and again, and with
// enough queries it never writes. Here a writer that waits stops new readers; it gets the map once
// those already reading are done.
//
// Tracking reads with lock_shared_ahead(): it passes a writer that waits, but not one that
// writes, so a pose does not queue behind a query's copy and then a whole integration. A long
// write lets such readers in midway with admitReadersAhead(), so that they wait for one part of
// it only; other readers and writers stay out until the writer is done. Passing is bounded, so
// that the writer is never starved by readers ahead whose holds overlap: a waiting writer is
// passed by at most kAheadPassesPerWait of them, and each admission lets in only those who
// waited when it began.
//
// A thread that already holds it shared may take it shared again (counted per thread, without
// waiting: queuing behind the writer would wait for itself). Taking it exclusively while holding
// it, or shared while holding it exclusively, deadlocks as with any shared mutex. Meets the
// SharedMutex requirements, for std::unique_lock and std::shared_lock; a shared hold is released by
// the thread that took it.
#include <condition_variable>
#include <mutex>

namespace semfuse::server {

class WriterFirstMutex {
 public:
  // One per tracking thread of a 2-core machine; more would delay a frame's integration further.
  static constexpr int kAheadPassesPerWait = 2;

  WriterFirstMutex() = default;
  WriterFirstMutex(const WriterFirstMutex&) = delete;
  WriterFirstMutex& operator=(const WriterFirstMutex&) = delete;

  void lock();
  bool try_lock();
  void unlock();
  void lock_shared();
  bool try_lock_shared();
  void unlock_shared();
  // A shared hold that passes waiting writers (released with unlock_shared()).
  void lock_shared_ahead();
  // Called by the exclusive holder: readers ahead who wait read now, then it holds it again.
  void admitReadersAhead();

 private:
  void lockShared(bool ahead_of_waiting_writers);

  std::mutex state_mutex_;
  std::condition_variable readers_may_enter_;
  std::condition_variable writer_may_enter_;
  int readers_ = 0;  // shared holds of distinct threads
  int readers_ahead_waiting_ = 0;
  int ahead_slots_ = 0;  // readers ahead who may still pass the waiting or admitting writer
  int writers_waiting_ = 0;
  bool writing_ = false;
  bool admitting_ = false;  // the writer lets readers ahead in and holds on to its turn
};

}  // namespace semfuse::server
