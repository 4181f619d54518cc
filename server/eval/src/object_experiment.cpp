#include "object_experiment.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <spdlog/spdlog.h>

#include "percent_text.hpp"
#include "semfuse/objects/grouping.hpp"
#include "semfuse/objects/object_figures.hpp"
#include "semfuse/objects/object_registry.hpp"
#include "semfuse/objects/surface_voxels.hpp"
#include "semfuse/segmentation/noise_model.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/volume/instance_integration.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::eval {
namespace {

// A surface voxel belongs to a true solid this close to it (depth noise moves the fused surface).
constexpr double kTruthDistanceVoxels = 2.0;

const LabelLegend& syntheticLegend() {
  static const LabelLegend legend = *builtinLegend("synthetic");
  return legend;
}

struct Query {
  objects::SurfaceVoxels surface;
  objects::Grouping grouping;
  objects::ObjectRegistry::Assignment ids;
};

}  // namespace

Result<ObjectRunResult> runObjectSource(const EvalSequence& sequence, const ObjectSource& source,
                                        const ObjectExperimentOptions& options) {
  if (sequence.instances.size() != sequence.frames.size())
    return makeError(sequence.name + " has no true instances (the object experiment needs the synthetic room)");
  auto created = volume::LabeledVolume::create(options.volume);
  if (!created) return makeError(created.error());
  volume::LabeledVolume volume = std::move(created).value();
  const synthetic::LabeledScene scene = synthetic::makeRoom();
  const std::map<uint32_t, LabelId> true_labels = instanceLabels(scene);
  objects::ObjectRegistry registry;

  ObjectRunResult result;
  result.source = source.name;
  result.run = sequence.name;
  std::map<uint32_t, uint32_t> previous_ids;  // true instance -> id of the object that matched it
  double query_ms = 0.0;
  const std::size_t frames = sequence.frames.size();
  for (std::size_t i = 0; i < frames; ++i) {
    const EvalFrame& frame = sequence.frames[i];
    Segmentation labels;
    labels.frame_seq = i;
    labels.labels = sequence.truth[i];
    labels.confidence = cv::Mat(labels.labels.size(), CV_32FC1, cv::Scalar(1.0f));
    if (source.pixel_noise > 0.0) {
      segmentation::NoiseParams noise;
      noise.probability = source.pixel_noise;
      noise.seed = options.seed;
      noise.candidates = sequence.present_labels;
      auto noisy = segmentation::addLabelNoise(labels, noise, i);
      if (!noisy) return makeError(noisy.error());
      labels = std::move(noisy).value();
    }
    auto stats = volume::integrate(volume, frame.depth, cv::Mat(), labels.labels, labels.confidence,
                                   sequence.intrinsics, frame.camera_to_world);
    if (!stats) return makeError(sequence.name + " frame " + std::to_string(i) + ": " + stats.error());
    if (source.instances) {
      auto instances = volume::integrateInstances(volume, frame.depth, labels.labels, sequence.instances[i],
                                                  sequence.intrinsics, frame.camera_to_world);
      if (!instances) return makeError(sequence.name + " frame " + std::to_string(i) + ": " + instances.error());
    }
    const bool last = i + 1 == frames;
    if ((i + 1) % static_cast<std::size_t>(options.query_every) != 0 && !last) continue;

    const auto start = std::chrono::steady_clock::now();
    Query query{objects::extractSurface(volume, syntheticLegend(), options.objects.min_instance_evidence), {}, {}};
    query.grouping = objects::groupSurface(query.surface, options.objects);
    query.ids = registry.assign(query.surface, query.grouping);
    const auto figures = objects::measureGroups(query.surface, query.grouping, options.objects.up);
    query_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ++result.queries;
    result.events += query.ids.events.size();

    const std::vector<uint32_t> truth =
        trueInstances(query.surface, scene, kTruthDistanceVoxels * options.volume.voxel_size);
    ObjectScore score =
        scoreObjects(query.surface, query.grouping, truth, true_labels, options.objects.min_object_area_m2);
    std::map<uint32_t, uint32_t> ids;
    for (std::size_t g = 0; g < query.grouping.groups.size(); ++g)
      if (score.instance_of_group[g] != 0) ids[score.instance_of_group[g]] = query.ids.ids[g];
    for (const auto& [instance, id] : ids) {
      const auto before = previous_ids.find(instance);
      if (before == previous_ids.end()) continue;
      ++result.compared_ids;
      if (before->second == id) ++result.kept_ids;
    }
    previous_ids = std::move(ids);
    if (last) {
      for (std::size_t g = 0; g < query.grouping.groups.size(); ++g) {
        const objects::Group& group = query.grouping.groups[g];
        if (group.fragment) continue;
        spdlog::debug("{} / {}: object {} {} {:.3f} m2, {} voxels, matches instance {}", source.name, sequence.name,
                      query.ids.ids[g], syntheticLegend().find(group.label)->name, group.area_m2, group.voxel_count,
                      score.instance_of_group[g]);
      }
      for (const auto& [instance, iou] : score.best_iou)
        spdlog::debug("{} / {}: instance {} ({}) best IoU {:.2f}", source.name, sequence.name, instance,
                      syntheticLegend().find(true_labels.at(instance))->name, iou);
      result.final_score = std::move(score);
    }
  }
  result.query_ms = result.queries ? query_ms / static_cast<double>(result.queries) : 0.0;
  return result;
}

ObjectScore scoreRoomMap(const volume::LabeledVolume& volume, const objects::ObjectParams& params) {
  const synthetic::LabeledScene scene = synthetic::makeRoom();
  const objects::SurfaceVoxels surface =
      objects::extractSurface(volume, syntheticLegend(), params.min_instance_evidence);
  const objects::Grouping grouping = objects::groupSurface(surface, params);
  const std::vector<uint32_t> truth = trueInstances(surface, scene, kTruthDistanceVoxels * volume.params().voxel_size);
  ObjectScore score = scoreObjects(surface, grouping, truth, instanceLabels(scene), params.min_object_area_m2);
  if (spdlog::should_log(spdlog::level::debug)) {
    // Per object: where it is and which true instances its voxels lie on.
    std::vector<Eigen::Vector3d> centre(grouping.groups.size(), Eigen::Vector3d::Zero());
    std::vector<std::map<uint32_t, std::size_t>> on(grouping.groups.size());
    for (std::size_t i = 0; i < surface.size(); ++i) {
      const int32_t g = grouping.group_of[i];
      if (g < 0) continue;
      centre[g] += volume.indexToWorld(surface[i].ijk);
      ++on[g][truth[i]];
    }
    for (std::size_t g = 0; g < grouping.groups.size(); ++g) {
      const objects::Group& group = grouping.groups[g];
      if (group.fragment) continue;
      std::string lies_on;
      for (const auto& [instance, count] : on[g]) lies_on += fmt::format(" {}:{}", instance, count);
      const Eigen::Vector3d c = centre[g] / static_cast<double>(std::max<uint64_t>(group.voxel_count, 1));
      spdlog::debug(
          "object of {}: {:.3f} m2, {} voxels at ({:.2f}, {:.2f}, {:.2f}), map instance {}, matches "
          "true instance {}; voxels on true instances{}",
          syntheticLegend().find(group.label)->name, group.area_m2, group.voxel_count, c.x(), c.y(), c.z(),
          group.instance, score.instance_of_group[g], lies_on);
    }
  }
  return score;
}

Result<std::vector<ObjectRunResult>> runObjectExperiment(const std::vector<const EvalSequence*>& sequences,
                                                         const ObjectExperimentOptions& options,
                                                         const ProgressFn& progress) {
  std::vector<ObjectRunResult> results;
  const std::size_t total = sequences.size() * options.sources.size();
  for (const ObjectSource& source : options.sources)
    for (const EvalSequence* sequence : sequences) {
      auto run = runObjectSource(*sequence, source, options);
      if (!run) return makeError(run.error());
      const ObjectRunResult& r = run.value();
      spdlog::info("objects, {} / {}: precision {}, recall {}, ids kept {} of {}, {} events, {:.1f} ms per query",
                   source.name, sequence->name, percent(r.final_score.total.precision()),
                   percent(r.final_score.total.recall()), r.kept_ids, r.compared_ids, r.events, r.query_ms);
      results.push_back(std::move(run).value());
      progress("objects", results.size(), total);
    }

  std::ofstream csv(options.out / "objects.csv");
  csv << "source,run,class,true_objects,found_objects,matched,precision,recall\n";
  for (const ObjectRunResult& r : results) {
    for (const auto& [label, c] : r.final_score.classes)
      csv << r.source << "," << r.run << "," << syntheticLegend().find(label)->name << "," << c.true_objects << ","
          << c.found_objects << "," << c.matched << "," << c.precision() << "," << c.recall() << "\n";
    const ClassCounts& c = r.final_score.total;
    csv << r.source << "," << r.run << ",all," << c.true_objects << "," << c.found_objects << "," << c.matched << ","
        << c.precision() << "," << c.recall() << "\n";
  }
  if (!csv) return makeError("cannot write " + (options.out / "objects.csv").string());

  // The markdown summary: per source, the classes summed over the runs.
  std::ofstream md(options.out / "objects.md");
  md << "# Objects: instances, ids and their score\n\n"
     << "Generated by `semfuse-eval --experiments 7` (`server/eval/src/object_experiment.hpp`): the synthetic room's "
     << "sequences fused frame by frame with the map's label rule, the objects queried every " << options.query_every
     << " frames of the growing map through one id registry, scored against the room's exact instances over "
        "surface voxels (IoU >= 0.5, same class). Objects smaller than "
     << options.objects.min_object_area_m2 << " m2 are fragments and not scored; true instances count when "
     << "their observed surface reaches that area.\n\n";
  for (const ObjectSource& source : options.sources) {
    std::map<LabelId, ClassCounts> classes;
    ClassCounts all;
    uint64_t kept = 0, compared = 0, events = 0, queries = 0;
    double ms = 0.0;
    std::size_t runs = 0;
    for (const ObjectRunResult& r : results) {
      if (r.source != source.name) continue;
      for (const auto& [label, c] : r.final_score.classes) classes[label] += c;
      all += r.final_score.total;
      kept += r.kept_ids;
      compared += r.compared_ids;
      events += r.events;
      queries += r.queries;
      ms += r.query_ms;
      ++runs;
    }
    md << "## " << source.name << "\n\n| class | true objects | found objects | matched | precision | recall |\n"
       << "|---|---|---|---|---|---|\n";
    for (const auto& [label, c] : classes)
      md << "| " << syntheticLegend().find(label)->name << " | " << c.true_objects << " | " << c.found_objects << " | "
         << c.matched << " | " << percent(c.precision()) << " | " << percent(c.recall()) << " |\n";
    md << "| **all** | " << all.true_objects << " | " << all.found_objects << " | " << all.matched << " | **"
       << percent(all.precision()) << "** | **" << percent(all.recall()) << "** |\n\n"
       << "Ids kept between consecutive queries: " << kept << " of " << compared << " ("
       << percent(compared ? double(kept) / double(compared) : 1.0) << ") over " << queries << " queries of " << runs
       << " runs; " << events << " events; " << std::fixed << std::setprecision(1) << (runs ? ms / double(runs) : 0.0)
       << " ms per query (mean, this machine).\n\n";
  }
  if (!md) return makeError("cannot write " + (options.out / "objects.md").string());
  return results;
}

}  // namespace semfuse::eval
