#include "semfuse/client/camera_publisher.hpp"

#include <algorithm>

#include "semfuse/dds/match.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/writer.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "server_discovery.hpp"

namespace semfuse::client {

using FrameMsg = semfuse_msg_dds__Frame_;

namespace {

// How long the first frame to a newly matched reader waits for that reader's acknowledgement.
constexpr auto kJoinHandshake = DDS_SECS(2);

wire::FrameEncoding wireEncoding(const CameraPublisherOptions& options) {
  wire::FrameEncoding encoding;
  switch (options.depth_encoding) {
    case DepthEncoding::kRaw16:
      encoding.depth = "16UC1";
      break;
    case DepthEncoding::kRawFloat:
      encoding.depth = "32FC1";
      break;
    case DepthEncoding::kPng16:
      encoding.depth = "png16";
      break;
    case DepthEncoding::kRvl:
      encoding.depth = "rvl";
      break;
  }
  switch (options.color_encoding) {
    case ColorEncoding::kNone:
      encoding.color = "";
      break;
    case ColorEncoding::kRaw:
      encoding.color = "rgb8";
      break;
    case ColorEncoding::kJpeg:
      encoding.color = "jpeg";
      break;
    case ColorEncoding::kPng:
      encoding.color = "png";
      break;
  }
  encoding.jpeg_quality = options.jpeg_quality;
  return encoding;
}

}  // namespace

struct CameraPublisher::Impl {
  Impl(const dds::Participant& participant, const CameraPublisherOptions& options)
      : encoding(wireEncoding(options)),
        participant(participant),
        topic(participant, dds::topics::kFrames),
        writer(topic, dds::qos::frames()) {}

  wire::FrameEncoding encoding;
  const dds::Participant& participant;
  dds::Topic<FrameMsg> topic;
  dds::Writer<FrameMsg> writer;
  std::size_t last_bytes = 0;
  int32_t readers_seen = 0;  // readers matched when the last frame was written
};

CameraPublisher::CameraPublisher(const dds::Participant& participant, CameraPublisherOptions options)
    : impl_(std::make_unique<Impl>(participant, options)) {}
CameraPublisher::~CameraPublisher() = default;
CameraPublisher::CameraPublisher(CameraPublisher&&) noexcept = default;
CameraPublisher& CameraPublisher::operator=(CameraPublisher&&) noexcept = default;

Status CameraPublisher::publish(const Frame& frame) {
  auto encoded = wire::encodeFrame(frame, impl_->encoding);
  if (!encoded) return encoded.errorInfo();
  const FrameMsg& msg = encoded.value().msg();
  impl_->last_bytes = msg.depth._length + msg.color._length;
  // Our writer matches a reader before that reader has matched us. Frames written in between
  // wait in the writer's two-deep history, and the next ones would push them out unseen: the
  // lost frames are the reader's first, so it cannot count them as a gap in the sequence. After
  // a reader joins, the next frame therefore waits for its acknowledgement, which the reader
  // sends only once it has matched us.
  const int32_t readers = dds::readersEverMatched(impl_->writer.handle());
  const bool reader_joined = readers > impl_->readers_seen;
  impl_->readers_seen = std::max(readers, impl_->readers_seen);
  Status written = impl_->writer.write(msg);
  if (written && reader_joined) (void)impl_->writer.waitForAcknowledgements(kJoinHandshake);
  return written;
}

bool CameraPublisher::waitForServer(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const auto server = detail::findServerParticipant(impl_->participant, timeout);
  if (!server) return false;
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  return detail::waitForReaderOf(impl_->writer.handle(), *server, std::max(left, std::chrono::milliseconds(0)));
}

bool CameraPublisher::waitForReader(std::chrono::milliseconds timeout) const {
  return impl_->writer.waitForReaders(1, DDS_MSECS(timeout.count()));
}

int CameraPublisher::matchedReaders() const { return impl_->writer.matchedReaders(); }

Status CameraPublisher::waitForAcknowledgements(std::chrono::milliseconds timeout) const {
  return impl_->writer.waitForAcknowledgements(DDS_MSECS(timeout.count()));
}

std::size_t CameraPublisher::lastPayloadBytes() const { return impl_->last_bytes; }

}  // namespace semfuse::client
