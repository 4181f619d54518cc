#pragma once
// The load bench's segmentation function: labels each pixel with valid depth by its depth band
// (25 cm) and image column third, from a handful of the legend's labels. It costs a few
// milliseconds, so the two segmenters at 10 Hz load the 2 cores with what a segmenter client
// does besides inference (taking frames off DDS, decoding them, publishing labels) and the server
// with a full label pass per segmentation, without a network's inference swamping the machine.
// Its regions are coherent, so the objects service finds instances in the map it builds.
#include <vector>

#include "semfuse/client/segmenter.hpp"
#include "semfuse/core/legend.hpp"

namespace semfuse::bench::load {

// Up to `count` label ids of the legend that are not background (in legend order).
std::vector<LabelId> foregroundLabels(const LabelLegend& legend, std::size_t count);

client::SegmentFunction depthBandSegmenter(std::vector<LabelId> labels);

}  // namespace semfuse::bench::load
