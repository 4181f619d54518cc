#include "semfuse/wire/image_message.hpp"

#include "semfuse/dds/sample.hpp"

namespace semfuse::wire {

void fillImageMessage(sensor_msgs_msg_dds__Image_& out, const cv::Mat& image, const char* encoding,
                      const char* frame_id) {
  if (image.empty()) return;
  out.width = static_cast<uint32_t>(image.cols);
  out.height = static_cast<uint32_t>(image.rows);
  out.step = static_cast<uint32_t>(image.cols * image.elemSize());
  out.is_bigendian = 0;
  dds::setString(out.encoding, encoding);
  dds::setString(out.header.frame_id, frame_id);
  const cv::Mat packed = image.isContinuous() ? image : image.clone();
  dds::setSequence(out.data, packed.ptr<uint8_t>(), packed.total() * packed.elemSize());
}

}  // namespace semfuse::wire
