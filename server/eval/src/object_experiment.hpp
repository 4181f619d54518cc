#pragma once
// The object experiment (semfuse-eval --experiments 7): the synthetic room's sequences fused frame
// by frame as the server fuses them (depth, labels with the map's rule and, for panoptic sources,
// instance maps), the objects queried every few frames of the growing map through one registry,
// as the server's objects service queries them. Scored against the room's exact instances
// (object_metric.hpp): precision and recall per class on the final map, and id stability: of the
// true instances matched by an object in two consecutive queries, the share whose object kept
// its id. Writes objects.csv and objects.md into the output folder.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "eval_sequence.hpp"
#include "object_metric.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/objects/object_params.hpp"
#include "semfuse/volume/labeled_volume.hpp"
#include "semfuse/volume/volume_params.hpp"

namespace semfuse::eval {

// Where a run's labels and instances come from.
struct ObjectSource {
  std::string name;          // "ground truth", "30% pixel noise", "panoptic ground truth", ...
  double pixel_noise = 0.0;  // the paper's pixel model on the labels (instances stay exact)
  bool instances = false;    // the segmenter is panoptic: instance maps are fused too
};

struct ObjectExperimentOptions {
  std::filesystem::path out;
  objects::ObjectParams objects;
  volume::VolumeParams volume;
  int query_every = 10;  // frames between two queries of the growing map
  uint64_t seed = 1;
  std::vector<ObjectSource> sources;
};

struct ObjectRunResult {
  std::string source, run;
  ObjectScore final_score;
  uint64_t kept_ids = 0, compared_ids = 0;  // id stability over consecutive queries
  std::size_t queries = 0;
  std::size_t events = 0;  // appeared, merged, split, vanished over the run
  double query_ms = 0.0;   // mean wall time of one query (surface, grouping, ids, figures)
};

using ProgressFn = std::function<void(const std::string& what, std::size_t done, std::size_t total)>;

// Runs every source on every sequence (which must carry true instances) and writes the files.
Result<std::vector<ObjectRunResult>> runObjectExperiment(const std::vector<const EvalSequence*>& sequences,
                                                         const ObjectExperimentOptions& options,
                                                         const ProgressFn& progress);

// One source on one sequence (tests use it with short sequences).
Result<ObjectRunResult> runObjectSource(const EvalSequence& sequence, const ObjectSource& source,
                                        const ObjectExperimentOptions& options);

// A map of the synthetic room fused elsewhere (a semfuse-server's map file): its objects, grouped
// as the objects service groups them, scored as the experiment scores its final map.
ObjectScore scoreRoomMap(const volume::LabeledVolume& volume, const objects::ObjectParams& params);

}  // namespace semfuse::eval
