#pragma once
// The distance field's answers (MapClient's distance queries) as dicts of numpy arrays, one entry
// per point or segment, and the queries' array arguments checked with a message that names them.
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "semfuse/client/map_client.hpp"

namespace semfuse::python {

namespace py = pybind11;

py::dict distanceSamplesDict(const std::vector<client::DistanceSample>& samples);
py::dict occupancyGridDict(client::OccupancyGrid grid);
py::dict semanticSamplesDict(const std::vector<client::SemanticSample>& samples);
py::dict semanticSliceDict(const client::SemanticSlice& slice);
py::dict segmentResultsDict(const std::vector<client::SegmentResult>& results);

// Segments from (N, 3) starts and ends; raises ValueError when their shapes differ.
std::vector<client::Segment> segmentsFromArrays(const py::handle& starts, const py::handle& ends);
// x, y in metres; raises ValueError naming `what`.
Eigen::Vector2d planePointFromArray(const py::handle& array, const char* what);

}  // namespace semfuse::python
