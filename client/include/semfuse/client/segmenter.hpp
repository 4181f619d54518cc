#pragma once
// Segmenter: subscribes to rt/semfuse/frames, runs a user function on each frame and publishes
// its labels on rt/semfuse/segmentations.
//
// The function runs on one worker thread that always takes the NEWEST frame: a function slower
// than the camera skips frames (counted in stats().skipped) instead of building a queue whose
// results would arrive later and later.
//
//   semfuse::client::Segmenter segmenter(participant, myFunction, {});
//   segmenter.start();
//   ...   // until done
//   segmenter.stop();
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::client {

// Frame -> labels (CV_16UC1, 0 = unlabeled) and confidence (CV_32FC1 in [0, 1], or empty = 1).
// The labels may be smaller than the frame (the server upsamples nearest-neighbour). The
// Segmenter fills in camera_id, frame_seq, stamp and segmenter_id.
using SegmentFunction = std::function<Result<Segmentation>(const Frame&)>;

struct SegmenterOptions {
  std::string segmenter_id = "semfuse-segmenter";
  std::string camera_id;  // only frames of this camera; empty = every camera
  int every = 1;          // segment every Nth frame of each camera (emulates a slow model)
  // Hold each result this long before publishing (a late model); the worker goes on with the
  // next frame meanwhile.
  std::chrono::milliseconds delay{0};
  // Selected frames kept while the function is busy, oldest given up first: 1 segments the newest
  // frame (live cameras); a replay that must label every frame keeps as many as it sends.
  std::size_t queue = 1;
};

struct SegmenterStats {
  uint64_t received = 0;      // frames seen on the topic
  uint64_t not_selected = 0;  // left out by camera_id or `every`
  uint64_t skipped = 0;       // given up for newer frames (the queue was full) before the worker got to them
  uint64_t segmented = 0;     // the function succeeded
  uint64_t published = 0;
  uint64_t failed = 0;  // undecodable frame, function error or write error
  double total_segment_ms = 0.0;
  double last_segment_ms = 0.0;
  double meanSegmentMs() const { return segmented ? total_segment_ms / segmented : 0.0; }
};

class Segmenter {
 public:
  Segmenter(const dds::Participant& participant, SegmentFunction function, SegmenterOptions options);
  ~Segmenter();  // stops the threads
  Segmenter(const Segmenter&) = delete;
  Segmenter& operator=(const Segmenter&) = delete;

  void start();
  // Lets the frame in hand finish and publish, then joins both threads.
  void stop();

  SegmenterStats stats() const;
  // True once a camera's frames writer is matched, waiting at most `timeout`.
  bool waitForCamera(std::chrono::milliseconds timeout) const;
  // Blocks until published segmentations were acknowledged, or the timeout.
  Status waitForAcknowledgements(std::chrono::milliseconds timeout) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semfuse::client
