#pragma once
// Map files: one .vdb holding
//   tsdf   FloatGrid, level-set class (viewable in Blender/Houdini), metres, active = observed
//   weight FloatGrid, score FloatGrid (both saved as half floats, their exact in-memory precision)
//   label  Int32Grid
//   color  Int32Grid 0x00RRGGBB (only when the volume has colour)
//   label_candidates  Int64Grid, the runners-up of a top-5 label rule (only for those rules)
//   free_space  MaskGrid of observed free space (free_space.hpp; when any was observed). Files
//          without it load with no free space: only the TSDF's voxels count as observed then.
// all with the same topology, plus file metadata: format version, every VolumeParams field as
// "semfuse:<key>" (volume_param_table.hpp; the label rule's since version 2), the label legend,
// frames integrated, checksums of the packed voxels and the sidecar, and the caller's extra
// key/value strings.
// A 32-byte trailer after OpenVDB's bytes seals the file with its length and a CRC-64 (other
// OpenVDB readers ignore it); load checks it before OpenVDB parses anything, because OpenVDB's
// reader trusts the sizes in a file and a corrupt one can make it allocate gigabytes or crash.
// Save is atomic (temporary file ".<name>.tmp-<pid>" in the same folder, fsync, rename, fsync of
// the folder). Load reads into a new volume: a corrupt or truncated file gives an error and
// touches nothing. save -> load reproduces the packed voxels bit for bit.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {

// 1: evidence rule only. 2: label rule metadata and the label sidecar grid holding the top-3
// candidates of the majority and bayes rules. 3: the sidecar holds the top-5 (10-bit label, 6-bit
// score each). 4: the weight drop-off (VolumeParams::weight_dropoff; older files load with the
// default). Files of versions 1 and 2 load when their rule is the evidence rule; a version 2
// majority or bayes map is refused, since its sidecar packs candidates another way.
inline constexpr int kMapFormatVersion = 4;

using MapExtraMetadata = std::map<std::string, std::string>;

struct LoadedMap {
  LabeledVolume volume;
  LabelLegend legend;
  MapExtraMetadata extra;
  int format_version = 0;
};

Status saveMap(const LabeledVolume& volume, const LabelLegend& legend, const std::filesystem::path& path,
               const MapExtraMetadata& extra = {});

// Errors: ErrorCode::kNotFound when there is no file, kInternal when it cannot be read, else
// kInvalidArgument (not a map, damaged, a version this build does not read).
Result<LoadedMap> loadMap(const std::filesystem::path& path);

// Removes the temporary files of the map at `path` whose writing process no longer runs (a kill
// during a save leaves one behind; the map itself stays intact) and logs each one. Temporary
// files of live processes, of other maps and other files are kept; errors are logged, never
// fatal. saveMap and loadMap call it, so a restarted server cleans up when it resumes. Process
// ids are this host's: do not share a map folder between hosts.
std::vector<std::filesystem::path> removeStaleTemporaries(const std::filesystem::path& path);

}  // namespace semfuse::volume
