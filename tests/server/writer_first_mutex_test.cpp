// The map's lock lets a waiting writer (the fusion thread with a frame) in before new readers
// (queries), and a reader that already holds it may take it again while a writer waits.
#include <atomic>
#include <chrono>
#include <mutex>
#include <shared_mutex>
#include <thread>

#include <gtest/gtest.h>

#include "eventually.hpp"
#include "writer_first_mutex.hpp"

using namespace semfuse::server;
using namespace std::chrono_literals;
using semfuse::testing::eventually;

namespace {

// Starts a thread that takes `mutex` exclusively (and notes when it has it), then releases it.
std::thread writer(WriterFirstMutex& mutex, std::atomic<bool>& wrote) {
  return std::thread([&] {
    std::unique_lock lock(mutex);
    wrote = true;
  });
}

// Whether a new reader on another thread is turned away within `patience`: once the writer
// waits, it must be (a reader-first lock lets every new reader in and never turns one away).
bool newReaderTurnedAway(WriterFirstMutex& mutex, std::chrono::milliseconds patience) {
  bool turned_away = false;
  std::thread reader([&] {
    const auto deadline = std::chrono::steady_clock::now() + patience;
    while (!turned_away && std::chrono::steady_clock::now() < deadline) {
      if (mutex.try_lock_shared()) {
        mutex.unlock_shared();
        std::this_thread::sleep_for(5ms);
      } else {
        turned_away = true;
      }
    }
  });
  reader.join();
  return turned_away;
}

}  // namespace

TEST(WriterFirstMutex, AWaitingWriterStopsNewReaders) {
  WriterFirstMutex mutex;
  std::atomic<bool> wrote{false};
  mutex.lock_shared();  // a query reading the map
  std::thread fusion = writer(mutex, wrote);
  EXPECT_TRUE(newReaderTurnedAway(mutex, 5s));
  EXPECT_FALSE(wrote);
  mutex.unlock_shared();
  fusion.join();
  EXPECT_TRUE(wrote);
  // Free again: readers come in.
  ASSERT_TRUE(mutex.try_lock_shared());
  mutex.unlock_shared();
}

TEST(WriterFirstMutex, AReaderTakesItAgainWhileAWriterWaits) {
  WriterFirstMutex mutex;
  std::atomic<bool> wrote{false};
  std::shared_lock outer(mutex);
  std::thread fusion = writer(mutex, wrote);
  EXPECT_TRUE(newReaderTurnedAway(mutex, 5s));  // the writer waits now
  {
    std::shared_lock inner(mutex);  // would wait for the writer, which waits for `outer`
    EXPECT_TRUE(mutex.try_lock_shared());
    mutex.unlock_shared();
  }
  EXPECT_FALSE(wrote);  // still held by `outer`
  outer.unlock();
  fusion.join();
  EXPECT_TRUE(wrote);
}

TEST(WriterFirstMutex, ExclusiveHoldsExcludeEveryoneElse) {
  WriterFirstMutex mutex;
  mutex.lock();
  std::thread other([&] {
    EXPECT_FALSE(mutex.try_lock_shared());
    EXPECT_FALSE(mutex.try_lock());
  });
  other.join();
  mutex.unlock();
  ASSERT_TRUE(mutex.try_lock());
  mutex.unlock();
}

TEST(WriterFirstMutex, AReaderAheadPassesAWaitingWriterButNotAWritingOne) {
  WriterFirstMutex mutex;
  std::atomic<bool> wrote{false};
  mutex.lock_shared();  // a query reading the map
  std::thread fusion = writer(mutex, wrote);
  ASSERT_TRUE(newReaderTurnedAway(mutex, 5s));  // the writer waits now
  std::thread tracker([&] {
    mutex.lock_shared_ahead();  // does not queue behind the waiting writer
    EXPECT_FALSE(wrote);
    mutex.unlock_shared();
  });
  tracker.join();
  mutex.unlock_shared();
  fusion.join();
  EXPECT_TRUE(wrote);

  // While the writer writes, a reader ahead waits for it.
  std::atomic<bool> read{false};
  mutex.lock();
  std::thread late_tracker([&] {
    mutex.lock_shared_ahead();
    read = true;
    mutex.unlock_shared();
  });
  std::this_thread::sleep_for(50ms);  // give it the chance to enter wrongly; it must not
  EXPECT_FALSE(read);
  mutex.unlock();
  late_tracker.join();
  EXPECT_TRUE(read);
}

TEST(WriterFirstMutex, AWriterLetsReadersAheadInMidwayAndOnlyThem) {
  WriterFirstMutex mutex;
  mutex.lock();  // the fusion thread integrating a frame
  std::atomic<bool> read{false};
  std::thread tracker([&] {
    mutex.lock_shared_ahead();
    read = true;
    mutex.unlock_shared();
  });
  // Between two batches: returns at once while nobody waits ahead, after the tracker read once it does.
  ASSERT_TRUE(eventually([&] {
    mutex.admitReadersAhead();
    return read.load();
  }));
  tracker.join();
  // The writer holds it again: nobody else is in.
  std::thread other([&] {
    EXPECT_FALSE(mutex.try_lock_shared());
    EXPECT_FALSE(mutex.try_lock());
  });
  other.join();
  mutex.unlock();
  ASSERT_TRUE(mutex.try_lock_shared());
  mutex.unlock_shared();
}

TEST(WriterFirstMutex, AWaitingWriterIsPassedByABoundedNumberOfReadersAhead) {
  WriterFirstMutex mutex;
  std::atomic<bool> wrote{false};
  mutex.lock_shared();  // a query reading the map
  std::thread fusion = writer(mutex, wrote);
  ASSERT_TRUE(newReaderTurnedAway(mutex, 5s));  // the writer waits now
  for (int pass = 0; pass < WriterFirstMutex::kAheadPassesPerWait; ++pass) {
    std::thread tracker([&] {
      mutex.lock_shared_ahead();
      mutex.unlock_shared();
    });
    tracker.join();  // passed: it did not wait for the writer, which waits for the query
  }
  std::atomic<bool> wrote_before_reading{false};
  std::thread one_too_many([&] {
    mutex.lock_shared_ahead();
    wrote_before_reading = wrote.load();
    mutex.unlock_shared();
  });
  std::this_thread::sleep_for(50ms);  // give it the chance to pass wrongly; it must not
  mutex.unlock_shared();
  fusion.join();
  one_too_many.join();
  EXPECT_TRUE(wrote_before_reading);
}
