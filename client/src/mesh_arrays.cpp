#include "semfuse/client/mesh_arrays.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

namespace semfuse::client {
namespace {

// A header longer than this is not a mesh the server wrote (its header is under 400 bytes).
constexpr std::size_t kMaxHeaderBytes = 64 * 1024;

enum class Scalar { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<Scalar> parseScalar(const std::string& name) {
  if (name == "char" || name == "int8") return Scalar::kInt8;
  if (name == "uchar" || name == "uint8") return Scalar::kUint8;
  if (name == "short" || name == "int16") return Scalar::kInt16;
  if (name == "ushort" || name == "uint16") return Scalar::kUint16;
  if (name == "int" || name == "int32") return Scalar::kInt32;
  if (name == "uint" || name == "uint32") return Scalar::kUint32;
  if (name == "float" || name == "float32") return Scalar::kFloat32;
  if (name == "double" || name == "float64") return Scalar::kFloat64;
  return std::nullopt;
}

std::size_t sizeOf(Scalar type) {
  switch (type) {
    case Scalar::kInt8:
    case Scalar::kUint8:
      return 1;
    case Scalar::kInt16:
    case Scalar::kUint16:
      return 2;
    case Scalar::kInt32:
    case Scalar::kUint32:
    case Scalar::kFloat32:
      return 4;
    case Scalar::kFloat64:
      return 8;
  }
  return 0;
}

// Little-endian bytes whatever the host's order.
uint64_t littleEndian(const uint8_t* p, std::size_t n) {
  uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}

double readScalar(Scalar type, const uint8_t* p) {
  const uint64_t bits = littleEndian(p, sizeOf(type));
  switch (type) {
    case Scalar::kInt8:
      return static_cast<int8_t>(bits);
    case Scalar::kUint8:
      return static_cast<uint8_t>(bits);
    case Scalar::kInt16:
      return static_cast<int16_t>(bits);
    case Scalar::kUint16:
      return static_cast<uint16_t>(bits);
    case Scalar::kInt32:
      return static_cast<int32_t>(bits);
    case Scalar::kUint32:
      return static_cast<uint32_t>(bits);
    case Scalar::kFloat32: {
      const auto narrow = static_cast<uint32_t>(bits);
      float f;
      std::memcpy(&f, &narrow, sizeof f);
      return f;
    }
    case Scalar::kFloat64: {
      double d;
      std::memcpy(&d, &bits, sizeof d);
      return d;
    }
  }
  return 0.0;
}

// A value in T's range (NaN to 0): a colour or label stored as a float must not overflow the cast.
template <class T>
T saturated(double value) {
  if (!(value > 0.0)) return 0;
  if (value >= static_cast<double>(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
  return static_cast<T>(value);
}

struct Property {
  std::string name;
  Scalar type = Scalar::kFloat32;
  bool is_list = false;
  Scalar count_type = Scalar::kUint8;  // lists only
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
  bool hasList() const {
    for (const auto& p : properties)
      if (p.is_list) return true;
    return false;
  }
  std::size_t scalarBytes() const {
    std::size_t bytes = 0;
    for (const auto& p : properties) bytes += sizeOf(p.type);
    return bytes;
  }
};

Error plyError(const std::string& message) { return makeError(ErrorCode::kInvalidArgument, "PLY: " + message); }

Result<std::vector<Element>> parseHeader(const uint8_t* data, std::size_t size, std::size_t& body) {
  const std::size_t limit = std::min(size, kMaxHeaderBytes);
  const std::string text(reinterpret_cast<const char*>(data), limit);
  const std::size_t end = text.find("end_header\n");
  if (text.compare(0, 4, "ply\n") != 0) return plyError("does not start with 'ply'");
  if (end == std::string::npos) return plyError("no end_header in the first " + std::to_string(limit) + " bytes");
  body = end + std::string("end_header\n").size();

  std::istringstream lines(text.substr(4, end - 4));
  std::vector<Element> elements;
  bool format_seen = false;
  std::string line;
  for (int number = 2; std::getline(lines, line); ++number) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    const std::string where = "header line " + std::to_string(number) + " ('" + line + "'): ";
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      std::string format, version;
      words >> format >> version;
      if (format != "binary_little_endian") return plyError(where + "only binary_little_endian is read");
      format_seen = true;
    } else if (keyword == "element") {
      Element element;
      if (!(words >> element.name >> element.count)) return plyError(where + "expected 'element <name> <count>'");
      elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (elements.empty()) return plyError(where + "property before any element");
      Property property;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> property.name;
        const auto count = parseScalar(count_type);
        const auto item = parseScalar(item_type);
        if (!count || !item || property.name.empty())
          return plyError(where + "expected 'property list <type> <type> <name>'");
        property.is_list = true;
        property.count_type = *count;
        property.type = *item;
      } else {
        const auto scalar = parseScalar(type);
        words >> property.name;
        if (!scalar || property.name.empty()) return plyError(where + "unknown property type '" + type + "'");
        property.type = *scalar;
      }
      elements.back().properties.push_back(std::move(property));
    } else {
      return plyError(where + "unknown keyword '" + keyword + "'");
    }
  }
  if (!format_seen) return plyError("no format line");
  return elements;
}

// Where the reader stands in the body; every read is checked against the end first.
class Cursor {
 public:
  Cursor(const uint8_t* data, std::size_t size, std::size_t at) : data_(data), size_(size), at_(at) {}
  std::size_t left() const { return size_ - at_; }
  const uint8_t* take(std::size_t n) {
    const uint8_t* p = data_ + at_;
    at_ += n;
    return p;
  }
  std::size_t offset() const { return at_; }

 private:
  const uint8_t* data_;
  std::size_t size_;
  std::size_t at_;
};

Status readVertices(const Element& element, Cursor& cursor, MeshArrays& out) {
  if (element.hasList()) return plyError("the vertex element has a list property");
  const std::size_t record = element.scalarBytes();
  if (record == 0 || element.count > cursor.left() / record)
    return plyError(std::to_string(element.count) + " vertices of " + std::to_string(record) +
                    " bytes need more than the " + std::to_string(cursor.left()) + " bytes left");
  // Where each property goes: an array and the component in its vertex's group, or nowhere.
  enum class Into { kNowhere, kPosition, kNormal, kColor, kLabel, kScore };
  struct Target {
    Into into = Into::kNowhere;
    int component = 0;
  };
  std::vector<Target> targets(element.properties.size());
  int xyz = 0, normal = 0, rgb = 0;
  bool label = false, score = false;
  for (std::size_t i = 0; i < element.properties.size(); ++i) {
    const std::string& name = element.properties[i].name;
    if (name == "x" || name == "y" || name == "z") {
      targets[i] = {Into::kPosition, name[0] - 'x'};
      ++xyz;
    } else if (name == "nx" || name == "ny" || name == "nz") {
      targets[i] = {Into::kNormal, name[1] - 'x'};
      ++normal;
    } else if (name == "red" || name == "green" || name == "blue") {
      targets[i] = {Into::kColor, name == "red" ? 0 : name == "green" ? 1 : 2};
      ++rgb;
    } else if (name == "label") {
      targets[i] = {Into::kLabel, 0};
      label = true;
    } else if (name == "score") {
      targets[i] = {Into::kScore, 0};
      score = true;
    }
  }
  if (xyz != 3) return plyError("vertices need the properties x, y and z");
  if (normal != 0 && normal != 3) return plyError("vertices have some but not all of nx, ny, nz");
  if (rgb != 0 && rgb != 3) return plyError("vertices have some but not all of red, green, blue");

  const std::size_t n = element.count;
  out.positions.assign(3 * n, 0.0F);
  if (normal) out.normals.assign(3 * n, 0.0F);
  if (rgb) out.colors.assign(3 * n, 0);
  if (label) out.labels.assign(n, 0);
  if (score) out.scores.assign(n, 0.0F);
  for (std::size_t v = 0; v < n; ++v) {
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
      const Property& p = element.properties[i];
      const double value = readScalar(p.type, cursor.take(sizeOf(p.type)));
      const std::size_t at = 3 * v + targets[i].component;
      switch (targets[i].into) {
        case Into::kNowhere:
          break;
        case Into::kPosition:
          out.positions[at] = static_cast<float>(value);
          break;
        case Into::kNormal:
          out.normals[at] = static_cast<float>(value);
          break;
        case Into::kColor:
          out.colors[at] = saturated<uint8_t>(value);
          break;
        case Into::kLabel:
          out.labels[v] = saturated<uint16_t>(value);
          break;
        case Into::kScore:
          out.scores[v] = static_cast<float>(value);
          break;
      }
    }
  }
  return Status::Ok();
}

Status readFaces(const Element& element, Cursor& cursor, std::size_t vertex_count, MeshArrays& out) {
  int lists = 0;
  for (const auto& p : element.properties) {
    if (!p.is_list) continue;
    if (p.name != "vertex_indices" && p.name != "vertex_index")
      return plyError("face list '" + p.name + "' is not vertex_indices");
    if (p.type == Scalar::kFloat32 || p.type == Scalar::kFloat64) return plyError("face indices are not integers");
    ++lists;
  }
  if (lists != 1) return plyError("the face element needs exactly one vertex_indices list");
  // Every face takes at least its scalars, a count and three indices: bound the count by the bytes.
  std::size_t least = 0;
  for (const auto& p : element.properties)
    least += p.is_list ? sizeOf(p.count_type) + 3 * sizeOf(p.type) : sizeOf(p.type);
  if (element.count > cursor.left() / least)
    return plyError(std::to_string(element.count) + " faces need more than the " + std::to_string(cursor.left()) +
                    " bytes left");
  out.faces.reserve(3 * element.count);
  for (uint64_t f = 0; f < element.count; ++f) {
    for (const auto& p : element.properties) {
      if (!p.is_list) {
        if (cursor.left() < sizeOf(p.type)) return plyError("face " + std::to_string(f) + " is cut short");
        cursor.take(sizeOf(p.type));
        continue;
      }
      if (cursor.left() < sizeOf(p.count_type)) return plyError("face " + std::to_string(f) + " is cut short");
      const double corners = readScalar(p.count_type, cursor.take(sizeOf(p.count_type)));
      if (corners != 3)
        return plyError("face " + std::to_string(f) + " has " + std::to_string(static_cast<long long>(corners)) +
                        " corners; only triangles are read");
      if (cursor.left() < 3 * sizeOf(p.type)) return plyError("face " + std::to_string(f) + " is cut short");
      for (int c = 0; c < 3; ++c) {
        const double index = readScalar(p.type, cursor.take(sizeOf(p.type)));
        if (index < 0 || index >= static_cast<double>(vertex_count))
          return plyError("face " + std::to_string(f) + " indexes vertex " +
                          std::to_string(static_cast<long long>(index)) + " of " + std::to_string(vertex_count));
        out.faces.push_back(static_cast<uint32_t>(index));
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Result<MeshArrays> parseMeshPly(const uint8_t* data, std::size_t size) {
  std::size_t body = 0;
  auto elements = parseHeader(data, size, body);
  if (!elements) return elements.errorInfo();
  Cursor cursor(data, size, body);
  MeshArrays out;
  bool vertices_read = false;
  for (const Element& element : elements.value()) {
    if (element.name == "vertex") {
      if (vertices_read) return plyError("two vertex elements");
      if (Status s = readVertices(element, cursor, out); !s) return s.errorInfo();
      vertices_read = true;
    } else if (element.name == "face") {
      if (!vertices_read) return plyError("faces before the vertices");
      if (Status s = readFaces(element, cursor, out.vertexCount(), out); !s) return s.errorInfo();
    } else {
      // Another element: skipped when its records have a fixed size.
      if (element.hasList()) return plyError("element '" + element.name + "' has a list and is not read");
      const std::size_t record = element.scalarBytes();
      if (record != 0 && element.count > cursor.left() / record)
        return plyError("element '" + element.name + "' needs more bytes than are left");
      cursor.take(record * element.count);
    }
  }
  if (!vertices_read) return plyError("no vertex element");
  if (cursor.left() != 0)
    return plyError(std::to_string(cursor.left()) + " bytes after the last element (at byte " +
                    std::to_string(cursor.offset()) + ")");
  return out;
}

}  // namespace semfuse::client
