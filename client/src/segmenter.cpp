#include "semfuse/client/segmenter.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"

namespace semfuse::client {

using FrameMsg = semfuse_msg_dds__Frame_;
using SegmentationMsg = semfuse_msg_dds__Segmentation_;

struct Segmenter::Impl {
  Impl(const dds::Participant& p, SegmentFunction fn, SegmenterOptions opts)
      : function(std::move(fn)),
        options(std::move(opts)),
        frames_topic(p, dds::topics::kFrames),
        segmentations_topic(p, dds::topics::kSegmentations),
        frames(frames_topic, dds::qos::frames()),
        segmentations(segmentations_topic, dds::qos::segmentations()),
        waitset(p),
        frames_ready(frames.handle(), DDS_ANY_STATE),
        wake(p) {
    waitset.attach(frames_ready.handle());
    waitset.attach(wake.handle());
  }

  // Receiver thread: takes every frame off the reader as it comes, so that DDS's keep-last
  // history never fills, and keeps the newest `queue` selected ones (still encoded).
  void receive() {
    while (!stopping) {
      auto woke = waitset.wait(DDS_MSECS(200));
      if (!woke) {
        spdlog::error("segmenter: {}", woke.error());
        return;
      }
      while (auto sample = frames.take()) {
        std::lock_guard lock(mutex);
        ++stats.received;
        const std::string camera = (*sample)->camera_id ? (*sample)->camera_id : "";
        if (!options.camera_id.empty() && options.camera_id != camera) {
          ++stats.not_selected;
          continue;
        }
        // Every Nth frame of each camera: which of a camera's frames are segmented must not
        // depend on how many frames other cameras sent in between.
        if (frames_seen[camera]++ % static_cast<uint64_t>(options.every) != 0) {
          ++stats.not_selected;
          continue;
        }
        if (waiting.size() >= std::max<std::size_t>(options.queue, 1)) {
          waiting.pop_front();
          ++stats.skipped;
        }
        waiting.push_back(std::move(*sample));
        slot_changed.notify_one();
      }
    }
  }

  // Worker thread: decode, segment and publish (or hand to the publisher, with a delay) the
  // oldest kept frame, one at a time.
  void work() {
    for (;;) {
      std::optional<dds::Sample<FrameMsg>> next;
      {
        std::unique_lock lock(mutex);
        slot_changed.wait(lock, [&] { return !waiting.empty() || stopping; });
        if (waiting.empty()) return;  // stopping with nothing left to do
        next = std::move(waiting.front());
        waiting.pop_front();
      }
      process(**next);
    }
  }

  void process(const FrameMsg& msg) {
    auto frame = wire::decodeFrame(msg);
    if (!frame) return fail("cannot decode " + frame.error());
    const auto started = std::chrono::steady_clock::now();
    auto result = function(frame.value());
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    if (!result) return fail("frame " + std::to_string(msg.seq) + ": " + result.error());
    Segmentation segmentation = std::move(result).value();
    segmentation.camera_id = frame.value().camera_id;
    segmentation.frame_seq = frame.value().seq;
    segmentation.stamp = frame.value().stamp;
    segmentation.segmenter_id = options.segmenter_id;
    {
      std::lock_guard lock(mutex);
      ++stats.segmented;
      stats.total_segment_ms += ms;
      stats.last_segment_ms = ms;
    }
    spdlog::debug("segmented frame {} of {} in {:.1f} ms", segmentation.frame_seq, segmentation.camera_id, ms);
    auto encoded = wire::encodeSegmentation(segmentation);
    if (!encoded) return fail(encoded.error());
    if (options.delay.count() == 0) return publish(encoded.value());
    std::lock_guard lock(mutex);
    held.push_back({std::chrono::steady_clock::now() + options.delay, std::move(encoded).value()});
    held_changed.notify_one();
  }

  // Publisher thread, only with a delay: writes each held result when it is due. The worker
  // meanwhile segments the next frame, so a late model is not also a slower one. Results
  // still held at stop() are published when due before the thread ends.
  void publishHeld() {
    std::unique_lock lock(mutex);
    for (;;) {
      held_changed.wait(lock, [&] { return !held.empty() || worker_done; });
      if (held.empty()) return;
      const auto due = held.front().due;
      if (std::chrono::steady_clock::now() < due) {
        held_changed.wait_until(lock, due);
        continue;
      }
      Held next = std::move(held.front());
      held.pop_front();
      lock.unlock();
      publish(next.encoded);
      lock.lock();
    }
  }

  void publish(const wire::EncodedSegmentation& encoded) {
    if (Status s = segmentations.write(encoded.msg()); !s) return fail(s.error());
    std::lock_guard lock(mutex);
    ++stats.published;
  }

  void fail(const std::string& message) {
    spdlog::warn("segmenter: {}", message);
    std::lock_guard lock(mutex);
    ++stats.failed;
  }

  SegmentFunction function;
  SegmenterOptions options;
  dds::Topic<FrameMsg> frames_topic;
  dds::Topic<SegmentationMsg> segmentations_topic;
  dds::Reader<FrameMsg> frames;
  dds::Writer<SegmentationMsg> segmentations;
  dds::WaitSet waitset;
  dds::ReadCondition frames_ready;
  dds::GuardCondition wake;

  mutable std::mutex mutex;
  std::condition_variable slot_changed;
  std::deque<dds::Sample<FrameMsg>> waiting;  // oldest first
  // Results held back by options.delay. One delay for all, so the oldest is always due first.
  struct Held {
    std::chrono::steady_clock::time_point due;
    wire::EncodedSegmentation encoded;
  };
  std::deque<Held> held;
  std::condition_variable held_changed;
  bool worker_done = false;
  SegmenterStats stats;
  std::map<std::string, uint64_t> frames_seen;  // per camera, for `every`; guarded by mutex
  std::atomic<bool> stopping{false};
  std::thread receiver;
  std::thread worker;
  std::thread publisher;
};

Segmenter::Segmenter(const dds::Participant& participant, SegmentFunction function, SegmenterOptions options)
    : impl_(std::make_unique<Impl>(participant, std::move(function), std::move(options))) {
  if (impl_->options.every < 1) impl_->options.every = 1;
}

Segmenter::~Segmenter() { stop(); }

void Segmenter::start() {
  if (impl_->receiver.joinable()) return;
  impl_->stopping = false;
  impl_->worker_done = false;
  impl_->receiver = std::thread([this] {
    setCurrentThreadName("sf-seg-receive");
    impl_->receive();
  });
  impl_->worker = std::thread([this] {
    setCurrentThreadName("sf-seg-work");
    impl_->work();
  });
  if (impl_->options.delay.count() > 0) {
    impl_->publisher = std::thread([this] {
      setCurrentThreadName("sf-seg-publish");
      impl_->publishHeld();
    });
  }
}

void Segmenter::stop() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.trigger();
  impl_->slot_changed.notify_all();
  if (impl_->receiver.joinable()) impl_->receiver.join();
  if (impl_->worker.joinable()) impl_->worker.join();
  {
    std::lock_guard lock(impl_->mutex);
    impl_->worker_done = true;
  }
  impl_->held_changed.notify_all();
  if (impl_->publisher.joinable()) impl_->publisher.join();
}

SegmenterStats Segmenter::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

bool Segmenter::waitForCamera(std::chrono::milliseconds timeout) const {
  return impl_->frames.waitForWriters(1, DDS_MSECS(timeout.count()));
}

Status Segmenter::waitForAcknowledgements(std::chrono::milliseconds timeout) const {
  return impl_->segmentations.waitForAcknowledgements(DDS_MSECS(timeout.count()));
}

}  // namespace semfuse::client
