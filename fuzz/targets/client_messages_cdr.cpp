// Fuzz target: the messages clients decode from the server: LabelLegend_ (first byte even) or
// TrackedPose_ (odd), serialized CDR after that byte -> CDR decoding -> wire::decodeLegend /
// wire::decodeTrackedPose. A decoded legend must pass validateLegend.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "semfuse/core/legend_io.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/message_codecs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0];
  ++data;
  --size;
  if (selector % 2 == 0) {
    auto sample = semfuse::dds::deserialize<semfuse_msg_dds__LabelLegend_>(data, size);
    if (!sample) return 0;
    auto legend = semfuse::wire::decodeLegend(*sample.value());
    if (legend) SEMFUSE_FUZZ_CHECK(semfuse::validateLegend(legend.value()).ok());
  } else {
    auto sample = semfuse::dds::deserialize<semfuse_msg_dds__TrackedPose_>(data, size);
    if (!sample) return 0;
    (void)semfuse::wire::decodeTrackedPose(*sample.value());
  }
  return 0;
}
