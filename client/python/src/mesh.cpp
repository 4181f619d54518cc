#include "arrays.hpp"
#include "python_types.hpp"
#include "runtime.hpp"
#include "semfuse/client/mesh_arrays.hpp"

namespace semfuse::python {

Mesh meshFromPly(std::vector<uint8_t>&& ply) {
  Result<client::MeshArrays> parsed = [&] {
    py::gil_scoped_release release;  // a large mesh takes some milliseconds
    return client::parseMeshPly(ply);
  }();
  if (!parsed) raiseCallFailure(client::Failure::kClient, "mesh reply: " + parsed.error(), parsed.errorCode());
  client::MeshArrays& a = parsed.value();
  const auto n = static_cast<py::ssize_t>(a.vertexCount());
  const auto faces = static_cast<py::ssize_t>(a.faceCount());
  Mesh mesh;
  mesh.vertices = vectorToArray(std::move(a.positions), {n, 3});
  mesh.faces = vectorToArray(std::move(a.faces), {faces, 3});
  // A property the PLY lacks is None; an empty mesh has empty arrays of every property.
  const auto optional = [n](auto&& values, std::vector<py::ssize_t> shape) -> py::object {
    if (values.empty() && n > 0) return py::none();
    return vectorToArray(std::move(values), std::move(shape));
  };
  mesh.normals = optional(std::move(a.normals), {n, 3});
  mesh.colors = optional(std::move(a.colors), {n, 3});
  mesh.labels = optional(std::move(a.labels), {n});
  mesh.scores = optional(std::move(a.scores), {n});
  mesh.ply = py::bytes(reinterpret_cast<const char*>(ply.data()), ply.size());
  return mesh;
}

}  // namespace semfuse::python
