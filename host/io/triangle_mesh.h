#pragma once
// An indexed triangle mesh with a face id per triangle (a CAD part's mesh, docs/cad.md "Meshing a
// part") and its writers: binary PLY, OBJ, binary STL, glTF (.glb, .gltf + .bin). Unlike the grid
// writers of io/sample_writer.h, whose connectivity follows from a grid, the triangles are given.
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/sample_writer.h>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace shapespline::io {

struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;                  // empty, or one unit normal per vertex
  std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from outside
  std::vector<int32_t> faceIds;                     // one per triangle (the part's face id)
};

// Whether `format` is one a triangle mesh is written as (.ply, .obj, .stl, .glb, .gltf).
bool triangleMeshFormat(OutputFormat format);

// Writes `mesh` to `out` (and `bin` for .gltf, the buffer file gltfBufferPath names) in `format`,
// in fp32 coordinates (fp64 in PLY when `doublePrecision`). `description` (a JSON object: the
// part's manifest, its SHA-256, deflection, angle, counts, open edges) goes where readers keep it:
// one PLY `comment part: ...` line, an OBJ comment, the glTF asset's extras, and the STL header's
// 80 bytes as far as it fits. The face ids become a PLY face property `int face_id`, OBJ groups
// (`g face_N`, one per run of a face's triangles), one glTF primitive per face (all sharing one
// POSITION and one NORMAL accessor, each with its own indices and `extras.face_id`) and, in STL,
// the attribute byte count // (16 bits per triangle, as several STL readers use it). Throws std::invalid_argument for a
// non-finite value, an index out of range, or a mesh a format cannot hold (vertex counts beyond
// 32-bit indices), naming the value.
void writeTriangleMesh(const TriangleMesh& mesh, OutputFormat format, const nlohmann::json& description,
                       bool doublePrecision, AtomicFile& out, AtomicFile* bin = nullptr);

}  // namespace shapespline::io
