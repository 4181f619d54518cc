#include "semfuse/client/camera_publisher.hpp"

#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/writer.hpp"
#include "wire_convert.hpp"

namespace semfuse::client {

using FrameMsg = semfuse_msg_dds__Frame_;

struct CameraPublisher::Impl {
  Impl(const dds::Participant& participant, const CameraPublisherOptions& options)
      : encoding{options.depth_encoding, options.color_encoding, options.jpeg_quality},
        topic(participant, dds::topics::kFrames),
        writer(topic, dds::qos::frames()) {}

  wire::FrameEncoding encoding;
  dds::Topic<FrameMsg> topic;
  dds::Writer<FrameMsg> writer;
  // Reused between frames: setSequence frees and reallocates, the struct itself stays.
  dds::Sample<FrameMsg> sample;
  std::size_t last_bytes = 0;
};

CameraPublisher::CameraPublisher(const dds::Participant& participant, CameraPublisherOptions options)
    : impl_(std::make_unique<Impl>(participant, options)) {}
CameraPublisher::~CameraPublisher() = default;
CameraPublisher::CameraPublisher(CameraPublisher&&) noexcept = default;
CameraPublisher& CameraPublisher::operator=(CameraPublisher&&) noexcept = default;

Status CameraPublisher::publish(const Frame& frame) {
  if (Status s = wire::encodeFrame(frame, impl_->encoding, *impl_->sample); !s) return s;
  impl_->last_bytes = impl_->sample->depth._length + impl_->sample->color._length;
  return impl_->writer.write(*impl_->sample);
}

bool CameraPublisher::waitForServer(std::chrono::milliseconds timeout) const {
  return impl_->writer.waitForReaders(1, DDS_MSECS(timeout.count()));
}

int CameraPublisher::matchedReaders() const { return impl_->writer.matchedReaders(); }

Status CameraPublisher::waitForAcknowledgements(std::chrono::milliseconds timeout) const {
  return dds::toStatus(dds_wait_for_acks(impl_->writer.handle(), DDS_MSECS(timeout.count())),
                       "wait for acknowledgements of the frames");
}

std::size_t CameraPublisher::lastPayloadBytes() const { return impl_->last_bytes; }

}  // namespace semfuse::client
