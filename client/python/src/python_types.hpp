#pragma once
// Results the bindings build for Python that have no C++ type of the client library's: the mesh
// as numpy arrays beside its PLY.
#include <cstdint>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace semfuse::python {

namespace py = pybind11;

struct Mesh {
  py::object vertices;  // (N, 3) float32
  py::object faces;     // (M, 3) uint32
  py::object normals;   // (N, 3) float32, or None
  py::object colors;    // (N, 3) uint8, or None
  py::object labels;    // (N,) uint16, or None
  py::object scores;    // (N,) float32, or None
  py::bytes ply;
};

// Reads the PLY the mesh service sent into arrays; raises semfuse.ClientError when it is not a
// mesh (the server's reply is outside input). Called with the interpreter's lock held.
Mesh meshFromPly(std::vector<uint8_t>&& ply);

}  // namespace semfuse::python
