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

// Throws std::invalid_argument unless `vertices` fit 32-bit indices (at most 2^32 - 1), which every
// format's indices are.
void checkVertexCount(uint64_t vertices);

// Writes `mesh` to `out` (and to `bin` for .gltf: the buffer file gltfBufferPath names) in
// `format`, in fp32 coordinates (fp64 in PLY when `doublePrecision`). `description` (a JSON object:
// the part's manifest, its SHA-256, deflection, angle, counts, open edges) goes where readers keep
// it: one PLY `comment part: ...` line, an OBJ `# part: ...` comment, the glTF asset's extras, and
// as much as fits of the STL header's 80 bytes. The face ids become a PLY face property
// `int face_id`, OBJ groups (`g face_N` before each run of a face's triangles), one glTF primitive
// per face in order of first appearance (all sharing one POSITION and one NORMAL accessor, each
// with its own indices and `extras.face_id`) and, in STL, the attribute byte count (the id's low 16
// bits, as several STL readers use it). Positions are written as they are (glTF: no re-centring),
// so float(p) reads back exactly. Every check comes before the first byte: throws
// std::invalid_argument for a non-finite value or one beyond the fp32 range of the file, an index
// out of range, a faceIds or normals count that does not match, or a mesh a format cannot hold
// (checkVertexCount; glTF: no triangles), naming the value.
void writeTriangleMesh(const TriangleMesh& mesh, OutputFormat format, const nlohmann::json& description,
                       bool doublePrecision, AtomicFile& out, AtomicFile* bin = nullptr);

}  // namespace shapespline::io
