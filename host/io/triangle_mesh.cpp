// The triangle-mesh writers (io/triangle_mesh.h): binary PLY, OBJ, binary STL and glTF. The mesh is
// in memory already, so each checks it whole, then writes it in one pass.
#include <shapespline/io/triangle_mesh.h>

#include <shapespline/core/point_records.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/gltf_model.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/version.h>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace shapespline::io {

static_assert(std::endian::native == std::endian::little, "the binary mesh writers assume a little-endian host");

bool triangleMeshFormat(OutputFormat format) {
  return format == OutputFormat::Ply || format == OutputFormat::Obj || format == OutputFormat::Stl || isGltf(format);
}

void checkVertexCount(uint64_t vertices) {
  if (vertices > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("the mesh has " + std::to_string(vertices) +
                                " vertices; 32-bit indices hold at most 4294967295");
  }
}

namespace {

// Every check before the first byte. Coordinates and normals must be finite and, unless `float64`,
// at most FLT_MAX in magnitude (beyond it the file would hold inf).
void checkMesh(const TriangleMesh& mesh, OutputFormat format, bool float64) {
  const size_t n = mesh.positions.size();
  checkVertexCount(n);
  if (!mesh.normals.empty() && mesh.normals.size() != n) {
    throw std::invalid_argument("normals has " + std::to_string(mesh.normals.size()) +
                                " entries; give none or one per position (" + std::to_string(n) + ")");
  }
  if (mesh.faceIds.size() != mesh.triangles.size()) {
    throw std::invalid_argument("faceIds has " + std::to_string(mesh.faceIds.size()) + " entries for " +
                                std::to_string(mesh.triangles.size()) + " triangles (one per triangle)");
  }
  if (isGltf(format) && mesh.triangles.empty()) {
    throw std::invalid_argument("the mesh has no triangles; a glTF mesh needs at least one primitive");
  }
  if (format == OutputFormat::Stl && mesh.triangles.size() > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("the mesh has " + std::to_string(mesh.triangles.size()) +
                                " triangles; STL counts at most 4294967295");
  }
  const double limit = recordRangeLimit(false, float64);
  auto checkVectors = [&](const std::vector<glm::dvec3>& v, const char* name) {
    for (size_t i = 0; i < v.size(); ++i) {
      for (int ax = 0; ax < 3; ++ax) {
        const double x = v[i][ax];
        if (std::isfinite(x) && std::abs(x) <= limit) continue;
        const std::string at = std::string(name) + "[" + std::to_string(i) + "]." + "xyz"[ax] + " = " + shortestText(x);
        throw std::invalid_argument(std::isfinite(x) ? at + " is beyond the fp32 range of the file (|v| <= " +
                                                           shortestText(limit) + ")"
                                                     : at + " is not finite");
      }
    }
  };
  checkVectors(mesh.positions, "positions");
  checkVectors(mesh.normals, "normals");
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.triangles[t][k] < n) continue;
      throw std::invalid_argument("triangles[" + std::to_string(t) + "][" + std::to_string(k) +
                                  "] = " + std::to_string(mesh.triangles[t][k]) +
                                  " is not a vertex index (the mesh has " + std::to_string(n) + " vertices)");
    }
  }
}

// The description on one line: JSON has no raw control characters in strings, and invalid UTF-8
// is replaced (U+FFFD), so no reader sees a second line.
std::string descriptionLine(const nlohmann::json& description) {
  return description.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void writePly(const TriangleMesh& mesh, const nlohmann::json& description, bool float64, AtomicFile& out) {
  const char* type = float64 ? "double" : "float";
  std::string h = "ply\nformat binary_little_endian 1.0\n";
  h += std::string(kPlyJobPrefix) + "part: " + descriptionLine(description) + "\n";
  h += "element vertex " + std::to_string(mesh.positions.size()) + "\n";
  for (const char* a : {"x", "y", "z"}) h += std::string("property ") + type + " " + a + "\n";
  if (!mesh.normals.empty()) {
    for (const char* a : {"nx", "ny", "nz"}) h += std::string("property ") + type + " " + a + "\n";
  }
  h += "element face " + std::to_string(mesh.triangles.size()) +
       "\nproperty list uchar uint vertex_indices\nproperty int face_id\nend_header\n";
  out.write(h);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    char* s = out.space(48);
    char* e = s;
    for (int ax = 0; ax < 3; ++ax) e = putBinaryValue(e, mesh.positions[i][ax], float64);
    if (!mesh.normals.empty()) {
      for (int ax = 0; ax < 3; ++ax) e = putBinaryValue(e, mesh.normals[i][ax], float64);
    }
    out.advance(static_cast<size_t>(e - s));
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    char* e = out.space(17);
    e[0] = 3;
    std::memcpy(e + 1, mesh.triangles[t].data(), 12);
    std::memcpy(e + 13, &mesh.faceIds[t], 4);
    out.advance(17);
  }
}

void writeObj(const TriangleMesh& mesh, const nlohmann::json& description, AtomicFile& out) {
  out.write(std::string(kObjJobPrefix) + "part: " + descriptionLine(description) + "\n");
  // The shortest text of each fp32 value (io/number_text.h): it reads back to that float exactly.
  auto vectorLine = [&](const char* tag, const glm::dvec3& v) {
    char* s = out.space(4 + 3 * (kMaxNumberChars + 1));
    char* e = s;
    for (const char* c = tag; *c; ++c) *e++ = *c;
    for (int ax = 0; ax < 3; ++ax) {
      *e++ = ' ';
      e = writeValue(e, v[ax], Precision::Float);
    }
    *e++ = '\n';
    out.advance(static_cast<size_t>(e - s));
  };
  for (const glm::dvec3& p : mesh.positions) vectorLine("v", p);
  for (const glm::dvec3& n : mesh.normals) vectorLine("vn", n);
  const bool normals = !mesh.normals.empty();
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (t == 0 || mesh.faceIds[t] != mesh.faceIds[t - 1]) {
      out.write("g face_" + std::to_string(mesh.faceIds[t]) + "\n");
    }
    char* s = out.space(4 + 3 * (2 * kMaxNumberChars + 4));
    char* e = s;
    *e++ = 'f';
    for (uint32_t i : mesh.triangles[t]) {
      *e++ = ' ';
      e = writeInteger(e, static_cast<unsigned long long>(i) + 1);
      if (normals) {
        *e++ = '/';
        *e++ = '/';
        e = writeInteger(e, static_cast<unsigned long long>(i) + 1);
      }
    }
    *e++ = '\n';
    out.advance(static_cast<size_t>(e - s));
  }
}

// The unit normal of triangle (a, b, c), counter-clockwise seen from its front, or 0 when it is
// degenerate. The cross product is scaled by its largest component before normalising, so neither
// tiny nor huge edges underflow or overflow the length.
glm::dvec3 triangleNormal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  glm::dvec3 n = glm::cross(b - a, c - a);
  const double m = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
  if (!(m > 0) || !std::isfinite(m)) return glm::dvec3(0.0);
  n /= m;
  return n / glm::length(n);
}

void writeStl(const TriangleMesh& mesh, const nlohmann::json& description, AtomicFile& out) {
  // The header must not start with "solid" (readers would take the file for ASCII STL).
  char header[80] = {};
  const std::string text = "shapespline part mesh " + descriptionLine(description);
  std::memcpy(header, text.data(), std::min(text.size(), sizeof header));
  out.write(header, sizeof header);
  const uint32_t count = static_cast<uint32_t>(mesh.triangles.size());
  out.write(&count, 4);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const glm::dvec3 n = triangleNormal(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
    char* s = out.space(50);
    char* e = s;
    for (int ax = 0; ax < 3; ++ax) e = putBinaryValue(e, n[ax], false);
    for (uint32_t i : tri) {
      for (int ax = 0; ax < 3; ++ax) e = putBinaryValue(e, mesh.positions[i][ax], false);
    }
    const uint16_t attribute = static_cast<uint16_t>(static_cast<uint32_t>(mesh.faceIds[t]) & 0xffffu);
    std::memcpy(e, &attribute, 2);
    out.advance(50);
  }
}

void writeGltf(const TriangleMesh& mesh, const nlohmann::json& description, AtomicFile& out, AtomicFile* bin) {
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = std::string("shapespline ") + SHAPESPLINE_VERSION_STRING;
  m.asset.extras = gltfValue(description);
  m.buffers.emplace_back();
  const size_t v = mesh.positions.size();
  m.buffers[0].data.reserve(v * (mesh.normals.empty() ? 12 : 24) + mesh.triangles.size() * 12 + 16);

  std::vector<float> values(v * 3);
  for (size_t i = 0; i < v; ++i) {
    for (int ax = 0; ax < 3; ++ax) values[i * 3 + static_cast<size_t>(ax)] = static_cast<float>(mesh.positions[i][ax]);
  }
  std::vector<double> min, max;
  gltfBounds(values, 3, min, max);
  const int position = addGltfAccessor(m, addGltfView(m, values.data(), values.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                                       TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, v, min, max);
  int normal = -1;
  if (!mesh.normals.empty()) {
    for (size_t i = 0; i < v; ++i) {
      for (int ax = 0; ax < 3; ++ax) values[i * 3 + static_cast<size_t>(ax)] = static_cast<float>(mesh.normals[i][ax]);
    }
    normal = addGltfAccessor(m, addGltfView(m, values.data(), values.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                             TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, v);
  }

  // One primitive per face id, in order of first appearance, its triangles in mesh order.
  std::vector<int32_t> order;
  std::map<int32_t, std::vector<uint32_t>> indices;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    auto [it, added] = indices.try_emplace(mesh.faceIds[t]);
    if (added) order.push_back(mesh.faceIds[t]);
    it->second.insert(it->second.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
  }
  tinygltf::Mesh gmesh;
  gmesh.name = "part";
  for (int32_t id : order) {
    const std::vector<uint32_t>& idx = indices[id];
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = position;
    if (normal >= 0) prim.attributes["NORMAL"] = normal;
    prim.indices =
        addGltfAccessor(m, addGltfView(m, idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, idx.size());
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.extras = tinygltf::Value(tinygltf::Value::Object{{"face_id", tinygltf::Value(static_cast<int>(id))}});
    gmesh.primitives.push_back(std::move(prim));
  }
  m.meshes.push_back(std::move(gmesh));
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "part";
  m.nodes.push_back(std::move(node));
  tinygltf::Scene scene;
  scene.nodes = {0};
  m.scenes.push_back(std::move(scene));
  m.defaultScene = 0;
  writeGltfModel(m, out, bin);
}

}  // namespace

void writeTriangleMesh(const TriangleMesh& mesh, OutputFormat format, const nlohmann::json& description,
                       bool doublePrecision, AtomicFile& out, AtomicFile* bin) {
  if (!triangleMeshFormat(format)) {
    throw std::invalid_argument("a triangle mesh is not written as ." + std::string(outputFormatName(format)) +
                                " (use .ply, .obj, .stl, .glb or .gltf)");
  }
  if (format == OutputFormat::Gltf && !bin) throw std::logic_error(".gltf output needs its .bin file");
  const bool float64 = doublePrecision && format == OutputFormat::Ply;
  checkMesh(mesh, format, float64);
  switch (format) {
    case OutputFormat::Ply: writePly(mesh, description, float64, out); break;
    case OutputFormat::Obj: writeObj(mesh, description, out); break;
    case OutputFormat::Stl: writeStl(mesh, description, out); break;
    case OutputFormat::Glb: writeGltf(mesh, description, out, nullptr); break;
    case OutputFormat::Gltf: writeGltf(mesh, description, out, bin); break;
    default: break;
  }
}

}  // namespace shapespline::io
