#include "server_config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <type_traits>

#include <fmt/format.h>

#include "semfuse/core/legend_io.hpp"
#include "semfuse/volume/volume_param_table.hpp"

namespace semfuse::server {
namespace {

// A numeric flag's value against its table row's range, with the row's message.
CLI::Validator rangeCheck(const volume::ParamField& field) {
  return CLI::Validator(
      [field](std::string& input) -> std::string {
        // CLI11 would read an empty value as 0, past this check.
        if (input.empty()) return "needs a number";
        char* end = nullptr;
        const double value = std::strtod(input.c_str(), &end);
        if (end == input.c_str()) return std::string();  // not a number: CLI11's conversion says so
        Status ok = volume::checkParam(field, value);
        return ok ? std::string() : ok.error();
      },
      field.range->text());
}

// A duration flag in seconds: a finite number in [0, max_s] (CLI11 reads "nan" and "inf" too).
CLI::Validator secondsCheck(double max_s) {
  const std::string range = "[0, " + fmt::format("{:g}", max_s) + "]";
  return CLI::Validator(
      [max_s, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double seconds = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(seconds) || seconds < 0.0 || seconds > max_s)
          return "must be seconds within " + range + ", got '" + text + "'";
        return {};
      },
      "SECONDS in " + range);
}

CLI::Validator labelRuleCheck() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        auto rule = volume::parseLabelRule(input);
        return rule ? std::string() : rule.error();
      },
      std::string(volume::labelRuleName(volume::LabelRule::kBayes)) + "|" +
          volume::labelRuleName(volume::LabelRule::kMajority) + "|" +
          volume::labelRuleName(volume::LabelRule::kEvidence));
}

// One flag per table row that has one, bound to its member, the member's value shown as default.
void addVolumeOptions(CLI::App& app, volume::VolumeParams& params, const std::string& group) {
  volume::forEachVolumeParam(params, [&app, &group](const volume::ParamField& field, auto& value) {
    if (field.flag == nullptr) return;
    using T = std::decay_t<decltype(value)>;
    const std::string name = std::string("--") + field.flag;
    CLI::Option* option = nullptr;
    if constexpr (std::is_same_v<T, volume::LabelRule>) {
      option =
          app.add_option_function<std::string>(
                 name, [&value](const std::string& text) { value = volume::parseLabelRule(text).value(); }, field.doc)
              ->check(labelRuleCheck())
              ->default_str(volume::labelRuleName(value));
    } else {
      option = app.add_option(name, value, field.doc)->capture_default_str();
    }
    if (field.range) option->check(rangeCheck(field));
    option->group(group);
  });
}

}  // namespace

void addServerOptions(CLI::App& app, ServerConfig& c) {
  auto* dds = "DDS";
  app.add_option("--domain-id", c.domain_id, "DDS domain id")->group(dds)->capture_default_str();
  app.add_option("--dds-profile", c.dds_profile,
                 "Cyclone DDS XML profile (e.g. deploy/dds/localhost.xml); default: $CYCLONEDDS_URI")
      ->group(dds);
  app.add_option("--server-id", c.server_id, "name reported in status")->group(dds)->capture_default_str();

  const std::string map = "Map";
  addVolumeOptions(app, c.volume, map);
  app.add_option("--legend", c.legend, "label legend: ade20k, voc, nyu40, synthetic or a YAML file")
      ->group(map)
      ->capture_default_str();

  auto* files = "Persistence";
  app.add_option("--map", c.map_file, "map file (.vdb): resumed from when it exists, autosaved to")->group(files);
  app.add_option("--autosave-period", c.autosave_period_s, "seconds between autosaves (0 = only on exit)")
      ->group(files)
      ->capture_default_str();

  auto* limits = "Ingest";
  app.add_option("--queue-per-camera", c.queue_per_camera, "frames queued per camera; when full the oldest is dropped")
      ->group(limits)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-queue-wait", c.max_queue_wait_s,
                 "seconds a camera's oldest queued frame may wait: a camera whose oldest frame waited longer, "
                 "and that has not caught up for 5 times as long, has its newest tracked and the ones before it "
                 "dropped (0 = track and integrate every queued frame in order, none skipped: replays)")
      ->group(limits)
      ->capture_default_str()
      ->check(secondsCheck(60.0));
  app.add_option("--history-frames", c.fusion.history_frames, "frames kept for late segmentations")
      ->group(limits)
      ->capture_default_str();
  app.add_option("--history-megabytes", c.fusion.history_megabytes, "memory bound of the frame history")
      ->group(limits)
      ->capture_default_str();
  app.add_option("--pending-segmentations", c.fusion.pending_segmentations,
                 "segmentations that may wait for their frame")
      ->group(limits)
      ->capture_default_str();
  app.add_option("--pending-timeout", c.fusion.pending_timeout_s, "seconds a segmentation waits for its frame")
      ->group(limits)
      ->capture_default_str();

  auto* tracking = "Tracking";
  app.add_option("--tracking-threads", c.fusion.tracking_threads,
                 "threads that track frames, each camera's in order, several cameras at once (0 = one per core, "
                 "at most 4)")
      ->group(tracking)
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  app.add_option("--refine-poses", c.refine_given_poses, "refine poses that come with frames by SDF alignment")
      ->group(tracking)
      ->capture_default_str();
  app.add_option("--track-color-weight", c.track_color_weight,
                 "weight of colour against depth when tracking cameras without poses; 0 for sensors whose colour "
                 "is not registered to their depth")
      ->check(CLI::Range(0.0f, 100.0f))
      ->group(tracking)
      ->capture_default_str();

  auto* queries = "Queries";
  app.add_option("--max-raycast-pixels", c.queries.max_raycast_pixels, "largest raycast image (width*height)")
      ->group(queries)
      ->capture_default_str();
  app.add_option("--mesh-chunk-bytes", c.queries.mesh_chunk_bytes, "PLY bytes per mesh reply")
      ->group(queries)
      ->capture_default_str();
  app.add_option("--objects-rate", c.objects_rate_hz,
                 "times per second the objects are regrouped in the background while the map changes and "
                 "somebody wants them (an objects query in the last 30 s, a reader of the object events): a "
                 "query with a max age is answered at once (0 = only on queries)")
      ->group(queries)
      ->capture_default_str()
      ->check(CLI::Range(0.0, 30.0));

  auto* status = "Status";
  app.add_option("--status-period", c.status_period_s, "seconds between status messages")
      ->group(status)
      ->capture_default_str();
  app.add_option("--stale-after", c.camera_stale_after_s, "a camera silent this long is reported stale")
      ->group(status)
      ->capture_default_str();

  addRosOptions(app, c.ros);
  addMapUpdateOptions(app, c.map_updates);
  addEsdfOptions(app, c.esdf);
}

Result<LabelLegend> serverLegend(const ServerConfig& config) {
  auto legend = resolveLegend(config.legend);
  if (!legend.ok()) return legend.errorInfo().prefixed("--legend " + config.legend + ": ");
  LabelLegend result = std::move(legend).value();
  auto& ids = result.background_ids;
  ids.insert(ids.end(), config.volume.background_labels.begin(), config.volume.background_labels.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return result;
}

Result<volume::VolumeParams> serverVolumeParams(const ServerConfig& config, const LabelLegend& legend) {
  volume::VolumeParams params = config.volume;
  const char* rule = volume::labelRuleName(params.label_rule);
  // The top-5 rules store runners-up in 10 bits: a legend beyond that would lose labels silently.
  if (volume::usesLabelSidecar(params.label_rule) && legend.maxId() > volume::kMaxRunnerUpLabel)
    return makeError(ErrorCode::kInvalidArgument, std::string("--label-rule ") + rule + " keeps label ids up to " +
                                                      std::to_string(volume::kMaxRunnerUpLabel) + ", but legend '" +
                                                      legend.name + "' has id " + std::to_string(legend.maxId()) +
                                                      "; use --label-rule evidence");
  params.label_classes = static_cast<int>(std::clamp<std::size_t>(legend.labels.size(), 2, 65535));
  params.background_labels = legend.background_ids;
  if (Status ok = params.validate(); !ok) return ok.errorInfo().prefixed("map parameters: ");
  return params;
}

std::chrono::steady_clock::duration frameQueueWait(const ServerConfig& config) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(config.max_queue_wait_s));
}

}  // namespace semfuse::server
