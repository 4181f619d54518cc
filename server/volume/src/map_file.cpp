#include "semfuse/volume/map_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <openvdb/io/Stream.h>
#include <spdlog/spdlog.h>

#include "map_layers.hpp"
#include "map_seal.hpp"
#include "semfuse/volume/volume_param_table.hpp"

namespace semfuse::volume {
namespace {
namespace fs = std::filesystem;
const char* const kExtraPrefix = "extra:";

// --- metadata <-> params, legend ----------------------------------------------------------

std::string joinIds(const std::vector<LabelId>& ids) {
  std::string out;
  for (LabelId id : ids) out += (out.empty() ? "" : " ") + std::to_string(id);
  return out;
}

Result<std::vector<LabelId>> parseIds(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  std::vector<LabelId> ids;
  long value = 0;
  while (in >> value) {
    if (value < 0 || value > 65535) return makeError(what + ": label id " + std::to_string(value) + " out of range");
    ids.push_back(static_cast<LabelId>(value));
  }
  if (!in.eof()) return makeError(what + ": not a list of label ids");
  return ids;
}

// Instance pairs seen apart as "low high low high ...".
std::string joinInstancePairs(const std::vector<uint64_t>& keys) {
  std::string out;
  for (uint64_t key : keys)
    out += (out.empty() ? "" : " ") + std::to_string(key >> 32) + " " + std::to_string(key & 0xFFFFFFFFu);
  return out;
}

Result<std::vector<uint64_t>> parseInstancePairs(const std::string& text, uint32_t next_id, const std::string& what) {
  std::istringstream in(text);
  std::vector<uint64_t> keys;
  long low = 0, high = 0;
  while (in >> low) {
    if (!(in >> high)) return makeError(what + ": an odd number of instance ids");
    if (low < 1 || high <= low || high >= static_cast<long>(next_id))
      return makeError(what + ": pair " + std::to_string(low) + " " + std::to_string(high) +
                       " is not two instance ids of the map, the lower first");
    keys.push_back(instancePairKey(static_cast<uint32_t>(low), static_cast<uint32_t>(high)));
  }
  if (!in.eof()) return makeError(what + ": not a list of instance ids");
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// One label per line: "id r g b name" (the name is the rest of the line).
Result<std::string> encodeLegend(const LabelLegend& legend) {
  std::string out;
  for (const LabelInfo& info : legend.labels) {
    if (info.name.find('\n') != std::string::npos)
      return makeError("legend: label " + std::to_string(info.id) + " has a newline in its name");
    out += std::to_string(info.id) + " " + std::to_string(info.rgb[0]) + " " + std::to_string(info.rgb[1]) + " " +
           std::to_string(info.rgb[2]) + " " + info.name + "\n";
  }
  return out;
}

Result<std::vector<LabelInfo>> decodeLegend(const std::string& text) {
  std::vector<LabelInfo> labels;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    long id = -1, r = -1, g = -1, b = -1;
    if (!(in >> id >> r >> g >> b) || id < 0 || id > 65535 || r < 0 || r > 255 || g < 0 || g > 255 || b < 0 || b > 255)
      return makeError("legend: malformed line '" + line + "'");
    std::string name;
    std::getline(in >> std::ws, name);
    labels.push_back(
        {static_cast<LabelId>(id), name, {static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(b)}});
  }
  return labels;
}

template <typename T>
Result<T> required(const openvdb::MetaMap& meta, const std::string& key) {
  const auto value = meta.getMetadata<openvdb::TypedMetadata<T>>(key);
  if (!value) return makeError("metadata '" + key + "' is missing or has the wrong type");
  return value->value();
}

// FNV-1a over the label sidecar's leaf origins and values (maps whose rule keeps candidates).
uint64_t sidecarChecksum(const LabelSidecarGrid::TreeType& tree) {
  uint64_t hash = 14695981039346656037ull;
  auto mix = [&hash](uint64_t value) {
    for (int byte = 0; byte < 8; ++byte) {
      hash ^= (value >> (8 * byte)) & 0xFFu;
      hash *= 1099511628211ull;
    }
  };
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord origin = leaf->origin();
    mix(static_cast<uint64_t>(static_cast<uint32_t>(origin.x())) << 32 | static_cast<uint32_t>(origin.y()));
    mix(static_cast<uint32_t>(origin.z()));
    const PackedLabelSidecar* values = leaf->buffer().data();
    for (openvdb::Index i = 0; i < LabelSidecarGrid::TreeType::LeafNodeType::SIZE; ++i)
      mix(static_cast<uint64_t>(values[i]));
  }
  return hash;
}

// One VolumeParams field as file metadata (the types map files have always used) and back.
openvdb::Metadata::Ptr paramMetadata(double value) { return openvdb::DoubleMetadata(value).copy(); }
openvdb::Metadata::Ptr paramMetadata(float value) { return openvdb::FloatMetadata(value).copy(); }
openvdb::Metadata::Ptr paramMetadata(int value) { return openvdb::Int32Metadata(value).copy(); }
openvdb::Metadata::Ptr paramMetadata(bool value) { return openvdb::BoolMetadata(value).copy(); }
openvdb::Metadata::Ptr paramMetadata(LabelRule rule) { return openvdb::StringMetadata(labelRuleName(rule)).copy(); }
openvdb::Metadata::Ptr paramMetadata(const std::vector<LabelId>& ids) {
  return openvdb::StringMetadata(joinIds(ids)).copy();
}

template <typename T>
Status readParam(const openvdb::MetaMap& meta, const std::string& key, T& value) {
  auto stored = required<T>(meta, key);
  if (!stored) return stored.errorInfo();
  value = stored.value();
  return Status::Ok();
}
Status readParam(const openvdb::MetaMap& meta, const std::string& key, LabelRule& rule) {
  auto name = required<std::string>(meta, key);
  if (!name) return name.errorInfo();
  auto parsed = parseLabelRule(name.value());
  if (!parsed) return makeError("metadata '" + key + "': " + parsed.error());
  rule = parsed.value();
  return Status::Ok();
}
Status readParam(const openvdb::MetaMap& meta, const std::string& key, std::vector<LabelId>& ids) {
  auto text = required<std::string>(meta, key);
  if (!text) return text.errorInfo();
  auto parsed = parseIds(text.value(), key);
  if (!parsed) return parsed.errorInfo();
  ids = std::move(parsed).value();
  return Status::Ok();
}

std::string metadataKey(const ParamField& field) { return std::string("semfuse:") + field.key; }

// Every field the file's version stores (the others keep their defaults). Version 1 predates
// label rules: its maps were fused with the evidence rule, whatever the default is now.
Result<VolumeParams> readVolumeParams(const openvdb::MetaMap& meta, int version) {
  VolumeParams params;
  if (version < 2) params.label_rule = LabelRule::kEvidence;
  Status status;
  forEachVolumeParam(params, [&](const ParamField& field, auto& value) {
    if (status.ok() && version >= field.since_map_version) status = readParam(meta, metadataKey(field), value);
  });
  if (!status) return status.errorInfo();
  return params;
}

openvdb::MetaMap fileMetadata(const LabeledVolume& volume, const LabelLegend& legend, const std::string& legend_text,
                              uint64_t checksum, const MapExtraMetadata& extra) {
  openvdb::MetaMap meta;
  meta.insertMeta("semfuse:format_version", openvdb::Int32Metadata(kMapFormatVersion));
  forEachVolumeParam(volume.params(), [&meta](const ParamField& field, const auto& value) {
    meta.insertMeta(metadataKey(field), *paramMetadata(value));
  });
  if (const LabelSidecarGrid* sidecar = volume.labelSidecarGrid())
    meta.insertMeta("semfuse:label_sidecar_checksum",
                    openvdb::Int64Metadata(static_cast<int64_t>(sidecarChecksum(sidecar->tree()))));
  meta.insertMeta("semfuse:frames_integrated", openvdb::Int64Metadata(static_cast<int64_t>(volume.framesIntegrated())));
  if (volume.instanceGrid()) {
    meta.insertMeta("semfuse:next_instance_id", openvdb::Int64Metadata(static_cast<int64_t>(volume.nextInstanceId())));
    meta.insertMeta("semfuse:instances_seen_apart",
                    openvdb::StringMetadata(joinInstancePairs(volume.instancePairsSeenApart())));
  }
  meta.insertMeta("semfuse:legend_name", openvdb::StringMetadata(legend.name));
  meta.insertMeta("semfuse:legend", openvdb::StringMetadata(legend_text));
  meta.insertMeta("semfuse:legend_background", openvdb::StringMetadata(joinIds(legend.background_ids)));
  meta.insertMeta("semfuse:checksum", openvdb::Int64Metadata(static_cast<int64_t>(checksum)));
  for (const auto& [key, value] : extra) meta.insertMeta(kExtraPrefix + key, openvdb::StringMetadata(value));
  return meta;
}

// --- atomic write ---------------------------------------------------------------------------

Status syncPath(const fs::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return makeError("cannot open " + path.string() + " to sync it");
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) return makeError("fsync of " + path.string() + " failed");
  return Status::Ok();
}

std::string temporaryPrefix(const fs::path& path) { return "." + path.filename().string() + ".tmp-"; }

Status writeAtomically(const fs::path& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& meta) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path temporary = folder / (temporaryPrefix(path) + std::to_string(::getpid()));
  auto fail = [&](const std::string& why) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    return makeError("saving map to " + path.string() + ": " + why);
  };
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return fail("cannot create " + temporary.string());
    // OpenVDB writes through the CRC, then the trailer seals what it wrote (map_seal.hpp).
    detail::CrcForwardingBuffer sealing(*out.rdbuf());
    std::ostream payload(&sealing);
    try {
      openvdb::io::Stream(payload).write(grids, meta);
    } catch (const std::exception& e) {
      return fail(std::string("OpenVDB write failed: ") + e.what());
    }
    if (!payload) return fail("write to " + temporary.string() + " failed (disk full?)");
    const std::string trailer = detail::sealTrailer(sealing.bytes(), sealing.crc());
    out.write(trailer.data(), static_cast<std::streamsize>(trailer.size()));
    out.close();
    if (!out) return fail("write to " + temporary.string() + " failed (disk full?)");
  }
  // Data on disk before the rename makes it visible; the folder entry on disk after it.
  if (Status s = syncPath(temporary, O_RDONLY); !s) return fail(s.error());
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) return fail("rename failed: " + error.message());
  if (Status s = syncPath(folder, O_RDONLY | O_DIRECTORY); !s) return makeError("saving map: " + s.error());
  return Status::Ok();
}

// The pid a temporary file name of this map ends with, or 0 for any other name.
pid_t temporaryWriter(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0 || name.size() - prefix.size() > 9)
    return 0;
  pid_t pid = 0;
  for (std::size_t i = prefix.size(); i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return 0;
    pid = pid * 10 + (name[i] - '0');
  }
  return pid;
}

// kill(pid, 0) delivers nothing; EPERM means the process exists but belongs to someone else.
bool processIsAlive(pid_t pid) { return ::kill(pid, 0) == 0 || errno == EPERM; }

// The whole file in memory: what is verified is exactly what OpenVDB then reads.
Result<std::string> readWholeFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    std::error_code ignored;
    return makeError(fs::exists(path, ignored) ? ErrorCode::kInternal : ErrorCode::kNotFound,
                     "cannot open " + path.string());
  }
  const std::streamoff size = in.tellg();
  if (size < 0) return makeError("cannot read " + path.string());
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  if (in.gcount() != size) return makeError("cannot read " + path.string() + " (it shrank while being read)");
  return bytes;
}

template <typename GridT>
typename GridT::Ptr findGrid(const openvdb::GridPtrVec& grids, const std::string& name) {
  for (const auto& grid : grids)
    if (grid && grid->getName() == name) return openvdb::gridPtrCast<GridT>(grid);
  return nullptr;
}

Result<LoadedMap> readMap(const fs::path& path) {
  auto file = readWholeFile(path);
  if (!file) return file.errorInfo();
  auto payload = detail::verifySeal(file.value());
  if (!payload) return makeError(payload.error());
  detail::MemoryReadBuffer buffer(payload.value());
  std::istream in(&buffer);
  openvdb::GridPtrVecPtr grids;
  openvdb::MetaMap::Ptr meta;
  try {
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    grids = stream.getGrids();
    meta = stream.getMetadata();
  } catch (const std::exception& e) {
    return makeError("not a readable OpenVDB file (" + std::string(e.what()) + ")");
  }
  if (!grids || !meta) return makeError("not a readable OpenVDB file");
  // The seal matched, so a short read means the writer itself wrote a broken stream.
  if (in.fail()) return makeError("the map data ends early");

  auto version = required<int32_t>(*meta, "semfuse:format_version");
  if (!version) return makeError("not a semfuse map: " + version.error());
  if (version.value() < 1 || version.value() > kMapFormatVersion)
    return makeError("map format version " + std::to_string(version.value()) +
                     " is not supported (this build reads 1.." + std::to_string(kMapFormatVersion) + ")");

  auto read_params = readVolumeParams(*meta, version.value());
  if (!read_params) return read_params.errorInfo();
  const VolumeParams& params = read_params.value();
  auto frames = required<int64_t>(*meta, "semfuse:frames_integrated");
  auto legend_name = required<std::string>(*meta, "semfuse:legend_name");
  auto legend_text = required<std::string>(*meta, "semfuse:legend");
  auto legend_background = required<std::string>(*meta, "semfuse:legend_background");
  auto checksum = required<int64_t>(*meta, "semfuse:checksum");
  for (const std::string* error :
       {frames ? nullptr : &frames.error(), legend_name ? nullptr : &legend_name.error(),
        legend_text ? nullptr : &legend_text.error(), legend_background ? nullptr : &legend_background.error(),
        checksum ? nullptr : &checksum.error()})
    if (error) return makeError(*error);
  if (version.value() < 3 && usesLabelSidecar(params.label_rule))
    return makeError("map format version " + std::to_string(version.value()) + " stores the '" +
                     labelRuleName(params.label_rule) +
                     "' rule's candidates as a top-3 list, which this build (top-5 since version 3) cannot read; "
                     "fuse the map again");
  auto created = LabeledVolume::create(params);
  if (!created) return makeError(created.error());
  if (frames.value() < 0) return makeError("metadata 'semfuse:frames_integrated' is negative");

  detail::MapLayers layers{findGrid<openvdb::FloatGrid>(*grids, "tsdf"), findGrid<openvdb::FloatGrid>(*grids, "weight"),
                           findGrid<openvdb::FloatGrid>(*grids, "score"),
                           findGrid<openvdb::Int32Grid>(*grids, "label")};
  if (!layers.tsdf || !layers.weight || !layers.score || !layers.label)
    return makeError("a float grid 'tsdf', 'weight', 'score' or an int32 grid 'label' is missing");
  auto packed = detail::mergeLayers(layers);
  if (!packed) return makeError(packed.error());
  openvdb::Int32Grid::Ptr color_grid;
  if (params.integrate_color) {
    color_grid = findGrid<openvdb::Int32Grid>(*grids, "color");
    if (!color_grid) return makeError("the int32 grid 'color' is missing");
    // Colour leaves mirror the geometry leaves; their active masks carry no meaning.
    bool same_leaves = color_grid->tree().leafCount() == packed.value()->leafCount();
    for (auto leaf = packed.value()->cbeginLeaf(); same_leaves && leaf; ++leaf)
      same_leaves = color_grid->tree().probeConstLeaf(leaf->origin()) != nullptr;
    if (!same_leaves) return makeError("the 'color' grid's leaves differ from the tsdf's");
  }
  if (detail::voxelChecksum(*packed.value(), color_grid ? &color_grid->tree() : nullptr) !=
      static_cast<uint64_t>(checksum.value()))
    return makeError("voxel checksum mismatch: the file is corrupt");

  LabelSidecarGrid::Ptr sidecar_grid;
  if (usesLabelSidecar(params.label_rule)) {
    sidecar_grid = findGrid<LabelSidecarGrid>(*grids, "label_candidates");
    if (!sidecar_grid)
      return makeError(std::string("the map fuses labels with the '") + labelRuleName(params.label_rule) +
                       "' rule but its int64 grid 'label_candidates' is missing");
    bool same_leaves = sidecar_grid->tree().leafCount() == packed.value()->leafCount();
    for (auto leaf = packed.value()->cbeginLeaf(); same_leaves && leaf; ++leaf)
      same_leaves = sidecar_grid->tree().probeConstLeaf(leaf->origin()) != nullptr;
    if (!same_leaves) return makeError("the 'label_candidates' grid's leaves differ from the tsdf's");
    auto sidecar_sum = required<int64_t>(*meta, "semfuse:label_sidecar_checksum");
    if (!sidecar_sum) return makeError(sidecar_sum.error());
    if (sidecarChecksum(sidecar_grid->tree()) != static_cast<uint64_t>(sidecar_sum.value()))
      return makeError("label sidecar checksum mismatch: the file is corrupt");
  }

  auto legend_labels = decodeLegend(legend_text.value());
  if (!legend_labels) return makeError(legend_labels.error());
  auto legend_bg = parseIds(legend_background.value(), "semfuse:legend_background");
  if (!legend_bg) return makeError(legend_bg.error());

  LoadedMap map{std::move(created).value(),
                LabelLegend{legend_name.value(), legend_labels.value(), legend_bg.value()},
                {},
                version.value()};
  map.volume.mutableGeometryGrid().setTree(packed.value());
  if (color_grid) map.volume.mutableColorGrid()->setTree(color_grid->treePtr());
  if (sidecar_grid) map.volume.mutableLabelSidecarGrid()->setTree(sidecar_grid->treePtr());
  // Observed free space (files written before it was kept have none: only the geometry grid's
  // voxels count as observed then).
  if (auto free_space = findGrid<FreeSpaceGrid>(*grids, "free_space")) map.volume.setFreeSpaceGrid(free_space);
  // Panoptic instance evidence, in maps fused with instance maps.
  if (auto instances = findGrid<InstanceGrid>(*grids, "instance")) {
    for (auto leaf = instances->tree().cbeginLeaf(); leaf; ++leaf)
      if (!packed.value()->probeConstLeaf(leaf->origin()))
        return makeError("the 'instance' grid has leaves where the tsdf has none");
    auto next_id = required<int64_t>(*meta, "semfuse:next_instance_id");
    if (!next_id) return makeError(next_id.error());
    if (next_id.value() < 1 || next_id.value() > static_cast<int64_t>(kMaxInstanceId) + 1)
      return makeError("metadata 'semfuse:next_instance_id' is out of range");
    // Maps saved before the pairs were kept have none: their instances join where the geometry
    // does until frames see them apart again.
    std::vector<uint64_t> apart;
    if (auto text = required<std::string>(*meta, "semfuse:instances_seen_apart")) {
      auto parsed = parseInstancePairs(text.value(), static_cast<uint32_t>(next_id.value()),
                                       "metadata 'semfuse:instances_seen_apart'");
      if (!parsed) return makeError(parsed.error());
      apart = std::move(parsed).value();
    }
    map.volume.setInstanceGrid(instances);
    map.volume.setNextInstanceId(static_cast<uint32_t>(next_id.value()));
    map.volume.setInstancePairsSeenApart(std::move(apart));
  }
  map.volume.setFramesIntegrated(static_cast<uint64_t>(frames.value()));
  // A consumer of changes that starts at revision 0 rebuilds from every leaf of the loaded map.
  map.volume.continueRevisionsFrom(0);
  for (auto it = meta->beginMeta(); it != meta->endMeta(); ++it)
    if (it->first.rfind(kExtraPrefix, 0) == 0 && it->second) map.extra[it->first.substr(6)] = it->second->str();
  return map;
}

}  // namespace

std::vector<fs::path> removeStaleTemporaries(const fs::path& path) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string prefix = temporaryPrefix(path);
  std::vector<fs::path> removed;
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end; entry.increment(error)) {
    const pid_t writer = temporaryWriter(entry->path().filename().string(), prefix);
    if (writer <= 0 || writer == ::getpid() || processIsAlive(writer)) continue;
    std::error_code remove_error;
    if (fs::remove(entry->path(), remove_error)) {
      spdlog::info("removed {}: a temporary map file of process {}, which is gone (killed while saving)",
                   entry->path().string(), writer);
      removed.push_back(entry->path());
    } else if (remove_error) {
      spdlog::warn("cannot remove the stale temporary map file {}: {}", entry->path().string(), remove_error.message());
    }
  }
  return removed;
}

Status saveMap(const LabeledVolume& volume, const LabelLegend& legend, const fs::path& path,
               const MapExtraMetadata& extra) {
  auto legend_text = encodeLegend(legend);
  if (!legend_text) return makeError("saving map to " + path.string() + ": " + legend_text.error());
  const detail::MapLayers layers = detail::splitLayers(volume);
  openvdb::GridCPtrVec grids{layers.tsdf, layers.weight, layers.score, layers.label};
  if (volume.colorGrid()) grids.push_back(volume.colorGridPtr());
  if (volume.labelSidecarGrid()) grids.push_back(volume.labelSidecarGridPtr());
  if (volume.freeSpaceGrid()) grids.push_back(volume.freeSpaceGridPtr());
  if (volume.instanceGrid()) grids.push_back(volume.instanceGridPtr());
  const uint64_t checksum =
      detail::voxelChecksum(volume.geometryGrid().tree(), volume.colorGrid() ? &volume.colorGrid()->tree() : nullptr);
  removeStaleTemporaries(path);
  return writeAtomically(path, grids, fileMetadata(volume, legend, legend_text.value(), checksum, extra));
}

Result<LoadedMap> loadMap(const fs::path& path) {
  openvdb::initialize();
  removeStaleTemporaries(path);
  auto map = readMap(path);
  if (!map) {
    Error error = map.errorInfo().prefixed("loading map " + path.string() + ": ");
    // Past finding the file, every failure is a file that is not a valid map.
    if (error.code == ErrorCode::kUnspecified) error.code = ErrorCode::kInvalidArgument;
    return error;
  }
  return map;
}

}  // namespace semfuse::volume
