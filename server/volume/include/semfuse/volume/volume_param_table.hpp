#pragma once
// The one list of VolumeParams' fields. Each row names a field once: its key (the member's name,
// and "semfuse:<key>" in map files), the server's flag and YAML key, the --help text, the range a
// numeric value must lie in, and the map format version that first stored it. From this list come
// the server's flags and config keys (server/core/src/server_config.cpp), the per-field checks of
// VolumeParams::validate() and the map files' metadata (map_file.cpp). The defaults are the
// member initializers of VolumeParams (volume_params.hpp), nowhere else.
//
// A new parameter: a member with its default in VolumeParams, a row in forEachVolumeParam.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/volume/volume_params.hpp"

namespace semfuse::volume {

// Bounds of a numeric parameter, each closed or open; a value must also be finite.
struct ParamRange {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = false;
  bool high_open = false;

  bool contains(double value) const;
  std::string text() const;  // "> 0", ">= 1", "in (0, 2048]"
};

struct ParamField {
  const char* key;   // VolumeParams member; map file metadata "semfuse:<key>"
  const char* flag;  // semfuse-server --<flag> and YAML key; nullptr: set by the server, not by a flag
  const char* doc;   // --help text
  std::optional<ParamRange> range = std::nullopt;  // numeric fields only
  int since_map_version = 1;                       // map files of older versions do not store it
};

// "max_weight must be a finite number in [1, 2048], got 5000" when `value` is outside the field's
// range (or not finite); ok for fields without a range.
Status checkParam(const ParamField& field, double value);

// "voxel_size=0.01 truncation=0.04 ... label_rule=bayes ... background_labels=[] integrate_color=true":
// every field by key, in table order (for logs, and to compare two VolumeParams).
std::string volumeParamsText(const VolumeParams& params);

// Calls visit(field, member) for every field of `params` (a VolumeParams, const or not).
template <class Params, class Visit>
void forEachVolumeParam(Params& params, Visit&& visit) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Weights and scores are stored as half floats, which hold every integer up to 2048 exactly.
  constexpr double kHalfExact = 2048.0;
  const ParamRange positive{0.0, kInf, true, false};
  visit(ParamField{"voxel_size", "voxel-size", "voxel edge, metres", positive}, params.voxel_size);
  visit(ParamField{"truncation", "truncation", "TSDF truncation distance, metres (at least one voxel)", positive},
        params.truncation);
  visit(ParamField{"max_weight", "max-weight", "TSDF weight clamp", ParamRange{1.0, kHalfExact}}, params.max_weight);
  visit(ParamField{"weight_dropoff", "weight-dropoff",
                   "depth behind the surface, as a fraction of the truncation, where an observation's weight "
                   "starts to fall linearly to 1/16 at -truncation (1: constant weight)",
                   ParamRange{0.0, 1.0, true, false}, 4},
        params.weight_dropoff);
  visit(ParamField{"max_label_score", "max-label-score", "label score clamp W_clamp",
                   ParamRange{0.0, kHalfExact, true, false}},
        params.max_label_score);
  visit(ParamField{"label_rule", "label-rule",
                   "label fusion: bayes (top-5 log-probabilities), majority (top-5 counts) or evidence (the "
                   "paper's Algorithm 1); see docs/eval",
                   std::nullopt, 2},
        params.label_rule);
  visit(ParamField{"label_likelihood", nullptr, "bayes rule: probability that a full-confidence pixel label is right",
                   ParamRange{0.0, 1.0, true, true}, 2},
        params.label_likelihood);
  visit(ParamField{"label_classes", nullptr, "bayes rule: number of labels (the server takes the legend's)",
                   ParamRange{2.0, 65535.0}, 2},
        params.label_classes);
  visit(ParamField{"min_depth", "min-depth", "ignore depth below, metres", positive}, params.min_depth);
  visit(ParamField{"max_depth", "max-depth", "ignore depth beyond, metres", positive}, params.max_depth);
  visit(ParamField{"background_labels", "background-labels",
                   "label ids that never change a voxel (added to the legend's own)"},
        params.background_labels);
  visit(ParamField{"integrate_color", "color", "fuse colour"}, params.integrate_color);
}

}  // namespace semfuse::volume
