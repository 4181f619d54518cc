#include "semfuse/wire/image_message.hpp"

#include <cstring>
#include <string>

#include <dds/dds.h>
#include <opencv2/imgproc.hpp>

#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/frame_codec.hpp"

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

namespace {

// What the decoders check before touching the pixels.
struct ImageLayout {
  int type = -1;
  int rows = 0, cols = 0;
  uint64_t row_bytes = 0, step = 0;
  bool bgr = false;
};

Result<ImageLayout> imageLayout(const sensor_msgs_msg_dds__Image_& image) {
  if (image.width > kMaxImageMessageSide || image.height > kMaxImageMessageSide)
    return makeError("image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " pixels exceeds " + std::to_string(kMaxImageMessageSide) + " a side");
  const std::string encoding = stringOf(image.encoding);
  ImageLayout layout;
  if (encoding == "32FC1") layout.type = CV_32FC1;
  else if (encoding == "32FC3") layout.type = CV_32FC3;
  else if (encoding == "16UC1" || encoding == "mono16") layout.type = CV_16UC1;
  else if (encoding == "8UC1" || encoding == "mono8") layout.type = CV_8UC1;
  else if (encoding == "rgb8" || encoding == "bgr8" || encoding == "8UC3") layout.type = CV_8UC3;
  else return makeError("unsupported image encoding '" + encoding + "'");
  if (image.is_bigendian && CV_ELEM_SIZE1(layout.type) > 1) return makeError("big-endian images are not supported");
  layout.bgr = encoding == "bgr8";
  layout.rows = static_cast<int>(image.height);
  layout.cols = static_cast<int>(image.width);
  layout.row_bytes = static_cast<uint64_t>(layout.cols) * CV_ELEM_SIZE(layout.type);
  layout.step = image.step == 0 ? layout.row_bytes : image.step;
  if (layout.step < layout.row_bytes ||
      image.data._length < layout.step * static_cast<uint64_t>(layout.rows - 1) + layout.row_bytes) {
    return makeError("image data shorter than its " + std::to_string(layout.cols) + "x" + std::to_string(layout.rows) +
                     " size");
  }
  if (image.data._buffer == nullptr) return makeError("image data missing");
  return layout;
}

// cv::Mat storage that Cyclone DDS allocated: the pixel buffer of a received sample (dds_alloc),
// handed to the Mat instead of copied, and given back with dds_free when the last Mat that shares
// it lets go. OpenCV's own pattern for foreign buffers (its Python bindings adopt numpy arrays so).
// What a Mat holding such a buffer allocates later (create() to another size) comes from OpenCV's
// default allocator, and is freed by it.
class DdsBufferAllocator final : public cv::MatAllocator {
 public:
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step, cv::AccessFlag flags,
                         cv::UMatUsageFlags usage) const override {
    return cv::Mat::getDefaultAllocator()->allocate(dims, sizes, type, data, step, flags, usage);
  }
  bool allocate(cv::UMatData* data, cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    return cv::Mat::getDefaultAllocator()->allocate(data, flags, usage);
  }
  void deallocate(cv::UMatData* data) const override {
    if (!data) return;
    dds_free(data->origdata);
    delete data;
  }
};

DdsBufferAllocator& ddsBufferAllocator() {
  static DdsBufferAllocator allocator;
  return allocator;
}

// The pixels of a checked image, copied row by row into a new Mat (BGR swapped to RGB).
cv::Mat copyImage(const sensor_msgs_msg_dds__Image_& image, const ImageLayout& l) {
  cv::Mat mat(l.rows, l.cols, l.type);
  for (int r = 0; r < l.rows; ++r)
    std::memcpy(mat.ptr(r), image.data._buffer + r * l.step, static_cast<std::size_t>(l.row_bytes));
  if (l.bgr) cv::cvtColor(mat, mat, cv::COLOR_BGR2RGB);
  return mat;
}

}  // namespace

Result<cv::Mat> decodeImageMessage(const sensor_msgs_msg_dds__Image_& image) {
  if (image.width == 0 || image.height == 0) return cv::Mat();
  auto layout = imageLayout(image);
  if (!layout) return makeError(layout.error());
  return copyImage(image, layout.value());
}

Result<cv::Mat> takeImageMessage(sensor_msgs_msg_dds__Image_& image) {
  if (image.width == 0 || image.height == 0) return cv::Mat();
  auto layout = imageLayout(image);
  if (!layout) return makeError(layout.error());
  const ImageLayout& l = layout.value();
  // A buffer the sample does not own, or BGR (swapped into a new Mat anyway), is copied.
  if (!image.data._release || l.bgr) return copyImage(image, l);
  uint8_t* pixels = image.data._buffer;
  cv::Mat mat(l.rows, l.cols, l.type, pixels, static_cast<std::size_t>(l.step));
  auto* storage = new cv::UMatData(&ddsBufferAllocator());
  storage->data = storage->origdata = pixels;
  storage->size = image.data._length;
  storage->refcount = 1;  // this Mat's reference, as Mat::create leaves it
  mat.u = storage;
  mat.allocator = &ddsBufferAllocator();
  // The sample no longer owns the pixels: freeing it leaves them to the Mat.
  image.data._buffer = nullptr;
  image.data._length = image.data._maximum = 0;
  image.data._release = false;
  return mat;
}

}  // namespace semfuse::wire
