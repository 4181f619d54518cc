#pragma once
// CameraPublisher: puts RGB-D frames on rt/semfuse/frames for the server to fuse.
//
//   semfuse::dds::Participant participant;
//   semfuse::client::CameraPublisher camera(participant, {});
//   camera.waitForServer(std::chrono::seconds(10));   // so no frame is lost to discovery
//   camera.publish(frame);                              // depth CV_32FC1 metres, colour CV_8UC3 RGB
//   camera.waitForAcknowledgements(std::chrono::seconds(5));
#include <chrono>
#include <memory>

#include "semfuse/client/encoding.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::client {

struct CameraPublisherOptions {
  DepthEncoding depth_encoding = DepthEncoding::kRaw16;
  ColorEncoding color_encoding = ColorEncoding::kJpeg;
  int jpeg_quality = 90;
};

// The participant must outlive the publisher.
class CameraPublisher {
 public:
  CameraPublisher(const dds::Participant& participant, CameraPublisherOptions options);
  ~CameraPublisher();
  CameraPublisher(CameraPublisher&&) noexcept;
  CameraPublisher& operator=(CameraPublisher&&) noexcept;

  // Encodes and writes one frame. Fails on a malformed frame or when the server's reader does not
  // acknowledge in time (the writer is reliable: a write blocks while the server is behind).
  // The first frame after a reader (a server, a segmenter) joins waits up to 2 s for that
  // reader's acknowledgement, so that discovery does not cost the reader its first frames.
  Status publish(const Frame& frame);

  // True once a semfuse server's frames reader is matched, waiting at most `timeout`. A server
  // is recognised by its status publication: other frames readers (segmenters) do not count.
  bool waitForServer(std::chrono::milliseconds timeout) const;
  // True once any frames reader is matched (a test's plain reader, a recorder).
  bool waitForReader(std::chrono::milliseconds timeout) const;
  int matchedReaders() const;
  // Blocks until every written frame was acknowledged by every matched reader, or the timeout.
  Status waitForAcknowledgements(std::chrono::milliseconds timeout) const;

  // Bytes of the last published frame's depth and colour payloads (for logs and benchmarks).
  std::size_t lastPayloadBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semfuse::client
