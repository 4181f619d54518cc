#pragma once
// How semfuse-query prints replies: an aligned table for people, JSON for scripts.
#include <string>
#include <vector>

#include "semfuse/client/map_client.hpp"
#include "semfuse/core/legend.hpp"

namespace semfuse::tools {

std::string statusTable(const client::ServerStatus& status);
std::string statusJson(const client::ServerStatus& status);

std::string objectsTable(const std::vector<client::ObjectInstance>& objects, const LabelLegend& legend);
std::string objectsJson(const std::vector<client::ObjectInstance>& objects, const LabelLegend& legend);

std::string regionTable(const client::RegionSummary& region, const LabelLegend& legend);
std::string regionJson(const client::RegionSummary& region, const LabelLegend& legend);

std::string samplesTable(const std::vector<Eigen::Vector3d>& points, const std::vector<client::VoxelSample>& samples,
                         const LabelLegend& legend);
std::string samplesJson(const std::vector<Eigen::Vector3d>& points, const std::vector<client::VoxelSample>& samples,
                        const LabelLegend& legend);

// The legend's name for a label, or "label N".
std::string labelName(const LabelLegend& legend, LabelId id);

}  // namespace semfuse::tools
