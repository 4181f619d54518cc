#pragma once
// Segmentation, TrackedPose, LabelLegend and ObjectEvents <-> their semfuse::msg::dds_ messages.
// Segmentation confidence encodings: "" (all 1.0), "8UC1" (0-255 = 0..1), "32FC1" (float 0..1).
#include <string>
#include <vector>

#include <msg.h>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/object_events.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/wire/owned_message.hpp"

namespace semfuse::wire {

using EncodedSegmentation = OwnedMessage<semfuse_msg_dds__Segmentation_>;
using EncodedTrackedPose = OwnedMessage<semfuse_msg_dds__TrackedPose_>;
using EncodedLegend = OwnedMessage<semfuse_msg_dds__LabelLegend_>;
using EncodedObjectEvents = OwnedMessage<semfuse_msg_dds__ObjectEvents_>;

const std::vector<std::string>& confidenceEncodings();  // "", 8UC1, 32FC1

// labels CV_16UC1; confidence CV_32FC1 of the same size in [0, 1], or empty (sent as "");
// instances CV_16UC1 of the same size (0 = no instance), or empty for a class-only segmenter.
Result<EncodedSegmentation> encodeSegmentation(const Segmentation& segmentation,
                                               const std::string& confidence_encoding = "8UC1");
// Validates sizes, encodings and confidence range; "" decodes to all-ones confidence. An instance
// map must have the labels' size, and instances on pixels none of which is labeled are refused.
// Checking against the frame size and the legend is the receiver's: validateSegmentationSize,
// validateLabels.
Result<Segmentation> decodeSegmentation(const semfuse_msg_dds__Segmentation_& msg);

EncodedTrackedPose encodeTrackedPose(const TrackedPose& pose);
Result<TrackedPose> decodeTrackedPose(const semfuse_msg_dds__TrackedPose_& msg);

EncodedLegend encodeLegend(const LabelLegend& legend, Stamp stamp = {});
// Sorts the labels by id and rejects what validateLegend rejects.
Result<LabelLegend> decodeLegend(const semfuse_msg_dds__LabelLegend_& msg);

EncodedObjectEvents encodeObjectEvents(const ObjectEvents& events);
// Rejects unknown event kinds and malformed sequences.
Result<ObjectEvents> decodeObjectEvents(const semfuse_msg_dds__ObjectEvents_& msg);

}  // namespace semfuse::wire
