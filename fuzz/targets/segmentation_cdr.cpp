// Fuzz target: a serialized semfuse::msg::dds_::Segmentation_ as the server's segmentation
// reader receives it -> CDR decoding -> wire::decodeSegmentation, then the checks the server
// makes against its frame and legend (validateSegmentationSize, validateLabels).
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "fuzz_support.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/validation.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const semfuse::LabelLegend legend = *semfuse::builtinLegend("voc");
  auto sample = semfuse::dds::deserialize<semfuse_msg_dds__Segmentation_>(data, size);
  if (!sample) return 0;
  auto segmentation = semfuse::wire::decodeSegmentation(*sample.value());
  if (!segmentation) return 0;
  const semfuse::Segmentation& s = segmentation.value();
  SEMFUSE_FUZZ_CHECK(s.labels.type() == CV_16UC1);
  SEMFUSE_FUZZ_CHECK(s.confidence.type() == CV_32FC1 && s.confidence.size() == s.labels.size());
  SEMFUSE_FUZZ_CHECK(semfuse::wire::validateConfidence(s.confidence).ok());
  SEMFUSE_FUZZ_CHECK(s.instances.empty() || (s.instances.type() == CV_16UC1 && s.instances.size() == s.labels.size()));
  (void)semfuse::wire::validateSegmentationSize(sample.value()->width, sample.value()->height, 640, 480);
  (void)semfuse::wire::validateLabels(s.labels, legend);
  return 0;
}
