// io/triangle_mesh.h: a closed octahedron with face ids written as binary PLY, OBJ, binary STL,
// .glb and .gltf + .bin, read back by readers we did not write:
//  * Debian's /usr/bin/python3 with numpy: the PLY header and body, the OBJ lines and the STL
//    records, printed as JSON (Python's repr of a float reads back exactly);
//  * assimp (`assimp info -r`): every file imports, with its vertex, face and mesh counts;
//  * the Khronos glTF validator: 0 errors and 0 warnings; tinygltf's loader: positions, normals,
//    each primitive's indices and extras.face_id, and the description in asset.extras.
// Values must round-trip exactly: float(p) in fp32 files, p in a PLY written in fp64. Every
// rejected mesh throws std::invalid_argument naming the value before a byte is written.
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/triangle_mesh.h>

#include "support/external_readers.h"
#include "support/temp_files.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;
using io::OutputFormat;
using io::TriangleMesh;
using nlohmann::json;

// An octahedron around an off-origin centre, with radii that are not fp32 values (so rounding
// to fp32 shows), outward normals and face ids in runs: 7 7 3 3 7 65541 65541 -2 (65541 and -2
// have low 16 bits 5 and 0xfffe: the STL attribute).
TriangleMesh octahedron() {
  TriangleMesh m;
  const glm::dvec3 c(0.1, -2.3, 7.7);
  const double r[3] = {1.1, 0.7, 1.3};
  for (int ax = 0; ax < 3; ++ax) {
    for (double s : {1.0, -1.0}) {
      glm::dvec3 d(0.0);
      d[ax] = s * r[ax];
      m.positions.push_back(c + d);
      glm::dvec3 n(0.0);
      n[ax] = s;
      m.normals.push_back(n);
    }
  }
  // Vertex 2 ax + (s < 0): one triangle per octant, counter-clockwise seen from outside.
  for (int sx = 0; sx < 2; ++sx) {
    for (int sy = 0; sy < 2; ++sy) {
      for (int sz = 0; sz < 2; ++sz) {
        std::array<uint32_t, 3> t{uint32_t(0 + sx), uint32_t(2 + sy), uint32_t(4 + sz)};
        if ((sx + sy + sz) % 2 == 1) std::swap(t[1], t[2]);
        m.triangles.push_back(t);
      }
    }
  }
  m.faceIds = {7, 7, 3, 3, 7, 65541, 65541, -2};
  return m;
}

json description() {
  return json{{"part", "bracket \"A\"\nline two"}, {"sha256", std::string(64, 'e')}, {"deflection", 0.01},
              {"faces", 4}, {"open_edges", 0}};
}

// The outward unit normal of triangle t (the test's own formula).
glm::dvec3 facetNormal(const TriangleMesh& m, size_t t) {
  const auto& tri = m.triangles[t];
  return glm::normalize(glm::cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]));
}

double f32(double v) { return static_cast<double>(static_cast<float>(v)); }

fs::path scratch(const std::string& name) { return processTempFile("trimesh", name); }

// Writes `mesh` to `path` (and its .bin for .gltf), committed.
void writeFile(const TriangleMesh& mesh, const fs::path& path, bool doublePrecision = false) {
  const OutputFormat format = io::outputFormatFromPath(path);
  io::AtomicFile out(path);
  std::optional<io::AtomicFile> bin;
  if (format == OutputFormat::Gltf) bin.emplace(io::gltfBufferPath(path));
  io::writeTriangleMesh(mesh, format, description(), doublePrecision, out, bin ? &*bin : nullptr);
  out.commit();
  if (bin) bin->commit();
}

// The independent reader: Python + numpy, printing what it read as JSON.
const char* kReader = R"PY(
import json, sys
import numpy as np
fmt, path = sys.argv[1], sys.argv[2]
data = open(path, 'rb').read()
out = {}
if fmt == 'ply':
    end = data.index(b'end_header\n') + len(b'end_header\n')
    lines = data[:end].decode('utf-8').split('\n')
    assert lines[0] == 'ply' and lines[1] == 'format binary_little_endian 1.0', lines[:2]
    elements, cur = [], None
    types = {'float': '<f4', 'double': '<f8', 'int': '<i4', 'uint': '<u4', 'uchar': 'u1'}
    for ln in lines[2:]:
        w = ln.split(' ')
        if w[0] == 'comment' and ln.startswith('comment part: '):
            out['description'] = json.loads(ln[len('comment part: '):])
        elif w[0] == 'element':
            cur = (w[1], int(w[2]), [])
            elements.append(cur)
        elif w[0] == 'property' and w[1] == 'list':
            assert (w[2], w[3]) == ('uchar', 'uint'), ln
            cur[2].append((w[4], 'u1', '<u4'))
        elif w[0] == 'property':
            cur[2].append((w[2], types[w[1]], None))
    pos = end
    for name, count, props in elements:
        dt = []
        for pname, t, item in props:
            if item:
                dt += [(pname + '_n', t), (pname, item, (3,))]
            else:
                dt.append((pname, t))
        a = np.frombuffer(data, dtype=np.dtype(dt), count=count, offset=pos)
        pos += a.nbytes
        if name == 'vertex':
            out['vertex_properties'] = [p[0] for p in props]
            out['vertex_type'] = props[0][1]
            out['positions'] = np.stack([a['x'], a['y'], a['z']], 1).astype(float).tolist()
            if 'nx' in a.dtype.names:
                out['normals'] = np.stack([a['nx'], a['ny'], a['nz']], 1).astype(float).tolist()
        elif name == 'face':
            assert (a['vertex_indices_n'] == 3).all()
            out['triangles'] = a['vertex_indices'].astype(int).tolist()
            out['face_ids'] = a['face_id'].astype(int).tolist()
    assert pos == len(data), (pos, len(data))
elif fmt == 'obj':
    out['positions'], out['normals'], out['triangles'], out['face_ids'], out['groups'] = [], [], [], [], []
    group = None
    for ln in data.decode('utf-8').split('\n'):
        w = ln.split()
        if not w:
            continue
        if ln.startswith('# part: '):
            out['description'] = json.loads(ln[len('# part: '):])
        elif w[0] == 'v':
            out['positions'].append([float(np.float32(x)) for x in w[1:]])
        elif w[0] == 'vn':
            out['normals'].append([float(np.float32(x)) for x in w[1:]])
        elif w[0] == 'g':
            group = int(w[1][len('face_'):])
            out['groups'].append(group)
        elif w[0] == 'f':
            tri = []
            for c in w[1:]:
                parts = c.split('/')
                if len(parts) > 1:
                    assert parts[1] == '' and parts[2] == parts[0], c
                tri.append(int(parts[0]) - 1)
            out['triangles'].append(tri)
            out['face_ids'].append(group)
elif fmt == 'stl':
    out['header'] = data[:80].split(b'\0')[0].decode('latin-1')
    h = data[:80]
    i = h.find(b'\0')
    out['header_zero_padded'] = i < 0 or h[i:] == b'\0' * (80 - i)
    n = int(np.frombuffer(data, '<u4', 1, 80)[0])
    dt = np.dtype([('n', '<f4', (3,)), ('v', '<f4', (3, 3)), ('attr', '<u2')])
    assert dt.itemsize == 50 and len(data) == 84 + 50 * n, (len(data), n)
    a = np.frombuffer(data, dt, n, 84)
    out['facet_normals'] = a['n'].astype(float).tolist()
    out['corners'] = a['v'].astype(float).tolist()
    out['attributes'] = a['attr'].astype(int).tolist()
print(json.dumps(out))
)PY";

json readWithPython(const std::string& format, const fs::path& file) {
  const fs::path script = scratch("reader.py");
  std::ofstream(script) << kReader;
  const ToolResult r = runTool(std::string(kSystemPython) + " " + shellQuote(script.string()) + " " + format + " " +
                               shellQuote(file.string()));
  EXPECT_EQ(r.rc, 0) << r.out;
  if (r.rc != 0) return json::object();
  return json::parse(r.out);
}

#define SKIP_UNLESS(why)                     \
  do {                                       \
    const std::string why_ = (why);          \
    if (!why_.empty()) GTEST_SKIP() << why_; \
  } while (0)

// `assimp info -r` of `file`: its summary counts (Vertices, Faces, Meshes) and each mesh's faces by
// name.
struct AssimpInfo {
  long vertices = -1, faces = -1, meshes = -1;
  std::map<std::string, long> facesByName;
};
AssimpInfo assimpInfo(const fs::path& file) {
  const ToolResult r = runTool("assimp info " + shellQuote(file.string()) + " -r");
  EXPECT_EQ(r.rc, 0) << r.out;
  AssimpInfo info;
  std::smatch m;
  if (std::regex_search(r.out, m, std::regex("\nVertices: +(\\d+)"))) info.vertices = std::stol(m[1]);
  if (std::regex_search(r.out, m, std::regex("\nFaces: +(\\d+)"))) info.faces = std::stol(m[1]);
  if (std::regex_search(r.out, m, std::regex("\nMeshes: +(\\d+)"))) info.meshes = std::stol(m[1]);
  const std::regex row("\\n +\\d+ \\(([^)]*)\\): \\[(\\d+) / \\d+ / (\\d+) \\|");
  for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), row); it != std::sregex_iterator(); ++it) {
    info.facesByName[(*it)[1]] += std::stol((*it)[3]);
  }
  EXPECT_GE(info.faces, 0) << r.out;
  return info;
}

std::map<int, long> trianglesById(const TriangleMesh& m) {
  std::map<int, long> n;
  for (int32_t id : m.faceIds) ++n[id];
  return n;
}

void expectVectors(const json& got, const std::vector<glm::dvec3>& want, bool float64, const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t i = 0; i < want.size(); ++i) {
    for (int ax = 0; ax < 3; ++ax) {
      const double w = float64 ? want[i][ax] : f32(want[i][ax]);
      EXPECT_EQ(got[i][ax].get<double>(), w) << what << "[" << i << "][" << ax << "]";
    }
  }
}

void expectTriangles(const json& got, const TriangleMesh& m) {
  ASSERT_EQ(got.size(), m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(got[t][k].get<uint32_t>(), m.triangles[t][k]) << "triangle " << t;
  }
}

TEST(TriangleMesh, PlyReadBackByNumpyAndAssimp) {
  SKIP_UNLESS(pythonNumpyMissing());
  const TriangleMesh m = octahedron();
  for (bool float64 : {false, true}) {
    SCOPED_TRACE(float64 ? "fp64" : "fp32");
    const fs::path file = scratch(float64 ? "d.ply" : "f.ply");
    writeFile(m, file, float64);
    const json r = readWithPython("ply", file);
    EXPECT_EQ(r.value("vertex_properties", json()), json({"x", "y", "z", "nx", "ny", "nz"}));
    EXPECT_EQ(r.value("vertex_type", ""), float64 ? "<f8" : "<f4");
    EXPECT_EQ(r.value("description", json()), description());
    expectVectors(r.value("positions", json::array()), m.positions, float64, "positions");
    expectVectors(r.value("normals", json::array()), m.normals, float64, "normals");
    expectTriangles(r.value("triangles", json::array()), m);
    EXPECT_EQ(r.value("face_ids", json()), json(m.faceIds));
    if (assimpMissing().empty()) {
      const AssimpInfo a = assimpInfo(file);
      EXPECT_EQ(a.vertices, 6);
      EXPECT_EQ(a.faces, 8);
    }
    fs::remove(file);
  }
}

TEST(TriangleMesh, PlyWithoutNormals) {
  SKIP_UNLESS(pythonNumpyMissing());
  TriangleMesh m = octahedron();
  m.normals.clear();
  const fs::path file = scratch("nn.ply");
  writeFile(m, file);
  const json r = readWithPython("ply", file);
  EXPECT_EQ(r.value("vertex_properties", json()), json({"x", "y", "z"}));
  expectVectors(r.value("positions", json::array()), m.positions, false, "positions");
  EXPECT_EQ(r.value("face_ids", json()), json(m.faceIds));
  fs::remove(file);
}

TEST(TriangleMesh, ObjReadBackByPythonAndAssimp) {
  SKIP_UNLESS(pythonNumpyMissing());
  for (bool normals : {true, false}) {
    SCOPED_TRACE(normals ? "with normals" : "without normals");
    TriangleMesh m = octahedron();
    if (!normals) m.normals.clear();
    const fs::path file = scratch(normals ? "n.obj" : "p.obj");
    writeFile(m, file);
    const json r = readWithPython("obj", file);
    EXPECT_EQ(r.value("description", json()), description());
    expectVectors(r.value("positions", json::array()), m.positions, false, "positions");
    expectVectors(r.value("normals", json::array()), m.normals, false, "normals");
    expectTriangles(r.value("triangles", json::array()), m);
    EXPECT_EQ(r.value("face_ids", json()), json(m.faceIds));
    // One group line per run of a face's triangles.
    EXPECT_EQ(r.value("groups", json()), json({7, 3, 7, 65541, -2}));
    if (assimpMissing().empty()) {
      const AssimpInfo a = assimpInfo(file);
      EXPECT_EQ(a.faces, 8);
      std::map<std::string, long> want;
      for (const auto& [id, n] : trianglesById(m)) want["face_" + std::to_string(id)] = n;
      EXPECT_EQ(a.facesByName, want);
    }
    fs::remove(file);
  }
}

TEST(TriangleMesh, StlReadBackByNumpyAndAssimp) {
  SKIP_UNLESS(pythonNumpyMissing());
  const TriangleMesh m = octahedron();
  const fs::path file = scratch("m.stl");
  writeFile(m, file);
  const json r = readWithPython("stl", file);
  const std::string header = r.value("header", "");
  const std::string want = ("shapespline part mesh " + description().dump()).substr(0, 80);
  EXPECT_EQ(header, want);
  EXPECT_TRUE(r.value("header_zero_padded", false));
  const json corners = r.value("corners", json::array()), normals = r.value("facet_normals", json::array());
  ASSERT_EQ(corners.size(), m.triangles.size());
  ASSERT_EQ(normals.size(), m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      for (int ax = 0; ax < 3; ++ax) {
        EXPECT_EQ(corners[t][k][ax].get<double>(), f32(m.positions[m.triangles[t][k]][ax])) << t << " " << k;
      }
    }
    // The writer's normal, rounded once to fp32, against the test's own: a few fp32 ulps of 1.
    const glm::dvec3 n = facetNormal(m, t);
    for (int ax = 0; ax < 3; ++ax) EXPECT_NEAR(normals[t][ax].get<double>(), n[ax], 4 * FLT_EPSILON) << "facet " << t;
    EXPECT_EQ(r["attributes"][t].get<int>(), static_cast<int>(static_cast<uint32_t>(m.faceIds[t]) & 0xffff));
  }
  if (assimpMissing().empty()) {
    const AssimpInfo a = assimpInfo(file);
    EXPECT_EQ(a.faces, 8);
    EXPECT_EQ(a.vertices, 24);  // STL has no shared vertices
  }
  fs::remove(file);
}

TEST(TriangleMesh, StlDegenerateTriangleHasZeroNormal) {
  SKIP_UNLESS(pythonNumpyMissing());
  TriangleMesh m = octahedron();
  m.triangles.push_back({0, 2, 2});  // two corners the same
  // Three distinct corners on a line, exactly (every difference and product is exact).
  for (double s : {1.0, 2.0, 3.0}) {
    m.positions.push_back(glm::dvec3(1.0, 2.0, 3.0) * s);
    m.normals.push_back(m.normals[0]);
  }
  m.triangles.push_back({6, 7, 8});
  m.faceIds.push_back(1);
  m.faceIds.push_back(1);
  const fs::path file = scratch("degenerate.stl");
  writeFile(m, file);
  const json r = readWithPython("stl", file);
  ASSERT_EQ(r["facet_normals"].size(), 10u);
  for (size_t t = 8; t < 10; ++t) EXPECT_EQ(r["facet_normals"][t], json({0.0, 0.0, 0.0})) << t;
  fs::remove(file);
}

// Bytes of accessor `a` of a loaded model, as T.
template <class T>
std::vector<T> accessorData(const tinygltf::Model& model, int a) {
  const tinygltf::Accessor& acc = model.accessors.at(static_cast<size_t>(a));
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<size_t>(acc.bufferView));
  const auto& buf = model.buffers.at(static_cast<size_t>(view.buffer)).data;
  const size_t comps = acc.type == TINYGLTF_TYPE_VEC3 ? 3 : 1;
  std::vector<T> v(acc.count * comps);
  EXPECT_LE(view.byteOffset + acc.byteOffset + v.size() * sizeof(T), buf.size());
  std::memcpy(v.data(), buf.data() + view.byteOffset + acc.byteOffset, v.size() * sizeof(T));
  return v;
}

TEST(TriangleMesh, GltfValidatedAndReadBackByTinygltf) {
  SKIP_UNLESS(gltfValidatorMissing());
  const TriangleMesh m = octahedron();
  for (const char* name : {"m.glb", "m.gltf"}) {
    SCOPED_TRACE(name);
    const fs::path file = scratch(name);
    writeFile(m, file);
    const GltfValidation v = validateGltf(file);
    EXPECT_EQ(v.errors, 0) << v.report.substr(0, 4000);
    EXPECT_EQ(v.warnings, 0) << v.report.substr(0, 4000);
    EXPECT_EQ(v.rc, 0) << v.report.substr(0, 4000);
    std::cout << "[validator] " << name << ": infos " << v.infos << " hints " << v.hints << "\n";

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool ok = file.extension() == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, file.string())
                                               : loader.LoadASCIIFromFile(&model, &err, &warn, file.string());
    ASSERT_TRUE(ok) << err << warn;
    ASSERT_EQ(model.meshes.size(), 1u);
    ASSERT_EQ(model.nodes.size(), 1u);
    EXPECT_TRUE(model.nodes[0].translation.empty());
    const auto& prims = model.meshes[0].primitives;
    // Face ids in order of first appearance, each with its triangles in mesh order.
    const std::vector<int> order{7, 3, 65541, -2};
    ASSERT_EQ(prims.size(), order.size());
    const int position = prims[0].attributes.at("POSITION"), normal = prims[0].attributes.at("NORMAL");
    const std::vector<float> p = accessorData<float>(model, position), n = accessorData<float>(model, normal);
    ASSERT_EQ(p.size(), m.positions.size() * 3);
    for (size_t i = 0; i < m.positions.size(); ++i) {
      for (int ax = 0; ax < 3; ++ax) {
        EXPECT_EQ(p[i * 3 + ax], static_cast<float>(m.positions[i][ax])) << i;
        EXPECT_EQ(n[i * 3 + ax], static_cast<float>(m.normals[i][ax])) << i;
      }
    }
    for (size_t k = 0; k < prims.size(); ++k) {
      EXPECT_EQ(prims[k].attributes.at("POSITION"), position);
      EXPECT_EQ(prims[k].attributes.at("NORMAL"), normal);
      EXPECT_EQ(prims[k].mode, TINYGLTF_MODE_TRIANGLES);
      ASSERT_TRUE(prims[k].extras.Has("face_id"));
      EXPECT_EQ(prims[k].extras.Get("face_id").GetNumberAsInt(), order[k]);
      EXPECT_EQ(model.accessors[static_cast<size_t>(prims[k].indices)].componentType,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
      std::vector<uint32_t> want;
      for (size_t t = 0; t < m.triangles.size(); ++t) {
        if (m.faceIds[t] == order[k]) want.insert(want.end(), m.triangles[t].begin(), m.triangles[t].end());
      }
      EXPECT_EQ(accessorData<uint32_t>(model, prims[k].indices), want) << "face " << order[k];
    }
    const tinygltf::Value& extras = model.asset.extras;
    ASSERT_TRUE(extras.IsObject());
    EXPECT_EQ(extras.Get("part").Get<std::string>(), description()["part"].get<std::string>());
    EXPECT_EQ(extras.Get("sha256").Get<std::string>(), description()["sha256"].get<std::string>());
    EXPECT_EQ(extras.Get("deflection").GetNumberAsDouble(), 0.01);
    EXPECT_EQ(extras.Get("faces").GetNumberAsInt(), 4);
    if (assimpMissing().empty()) {
      const AssimpInfo a = assimpInfo(file);
      EXPECT_EQ(a.faces, 8);
      EXPECT_EQ(a.meshes, 4);  // a primitive per face id
    }
    fs::remove(file);
    if (file.extension() == ".gltf") {
      EXPECT_TRUE(fs::exists(io::gltfBufferPath(file)));
      fs::remove(io::gltfBufferPath(file));
    }
  }
}

// The error of writing `mesh` as `format`; nothing may have been written.
std::string refusal(const TriangleMesh& mesh, OutputFormat format, bool doublePrecision = false) {
  const fs::path file = scratch("refused." + std::string(io::outputFormatName(format)));
  io::AtomicFile out(file);
  io::AtomicFile bin(io::gltfBufferPath(file));
  try {
    io::writeTriangleMesh(mesh, format, description(), doublePrecision, out, &bin);
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(out.bytesWritten(), 0u);
    EXPECT_EQ(bin.bytesWritten(), 0u);
    return e.what();
  }
  ADD_FAILURE() << "no error for " << io::outputFormatName(format);
  return "";
}

const OutputFormat kFormats[] = {OutputFormat::Ply, OutputFormat::Obj, OutputFormat::Stl, OutputFormat::Glb,
                                 OutputFormat::Gltf};

TEST(TriangleMesh, RefusesBadMeshesBeforeWriting) {
  for (OutputFormat f : kFormats) {
    SCOPED_TRACE(std::string(io::outputFormatName(f)));
    TriangleMesh m = octahedron();
    m.triangles[5][1] = 99;
    EXPECT_EQ(refusal(m, f), "triangles[5][1] = 99 is not a vertex index (the mesh has 6 vertices)");

    m = octahedron();
    m.positions[3].y = std::nan("");
    EXPECT_EQ(refusal(m, f), "positions[3].y = nan is not finite");

    m = octahedron();
    m.normals[4].z = -std::numeric_limits<double>::infinity();
    EXPECT_EQ(refusal(m, f), "normals[4].z = -inf is not finite");

    m = octahedron();
    m.positions[2].x = 1e39;  // finite, but inf in fp32
    EXPECT_NE(refusal(m, f).find("positions[2].x = 1e+39 is beyond the fp32 range"), std::string::npos);

    m = octahedron();
    m.faceIds.pop_back();
    EXPECT_EQ(refusal(m, f), "faceIds has 7 entries for 8 triangles (one per triangle)");

    m = octahedron();
    m.normals.pop_back();
    EXPECT_EQ(refusal(m, f), "normals has 5 entries; give none or one per position (6)");
  }
  // fp64 PLY holds what fp32 cannot.
  TriangleMesh big = octahedron();
  big.positions[2].x = 1e39;
  const fs::path file = scratch("big.ply");
  EXPECT_NO_THROW(writeFile(big, file, true));
  fs::remove(file);
  // glTF primitives cannot be empty.
  TriangleMesh empty;
  EXPECT_NE(refusal(empty, OutputFormat::Glb).find("no triangles"), std::string::npos);
}

TEST(TriangleMesh, VertexCountBeyond32BitIndicesIsRefused) {
  EXPECT_NO_THROW(io::checkVertexCount(std::numeric_limits<uint32_t>::max()));
  try {
    io::checkVertexCount(uint64_t{1} << 32);
    ADD_FAILURE() << "2^32 vertices accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "the mesh has 4294967296 vertices; 32-bit indices hold at most 4294967295");
  }
}

TEST(TriangleMesh, FormatsAndStlExtension) {
  EXPECT_EQ(io::outputFormatFromPath("part.STL"), OutputFormat::Stl);
  EXPECT_EQ(io::outputFormatName(OutputFormat::Stl), "stl");
  for (OutputFormat f : kFormats) EXPECT_TRUE(io::triangleMeshFormat(f));
  for (OutputFormat f : {OutputFormat::Csv, OutputFormat::Npy, OutputFormat::RawF32, OutputFormat::RawF64,
                         OutputFormat::Svg})
    EXPECT_FALSE(io::triangleMeshFormat(f));
  // The grid commands refuse .stl, naming -o; the grid writers never make one.
  try {
    io::requireGridFormat(OutputFormat::Stl, "x.stl", "-o");
    ADD_FAILURE() << ".stl accepted for a grid";
  } catch (const io::OutputPathError& e) {
    EXPECT_EQ(e.option(), "-o");
    EXPECT_NE(e.reason().find("STL is written for part meshes only"), std::string::npos) << e.reason();
  }
  EXPECT_NO_THROW(io::requireGridFormat(OutputFormat::Ply, "x.ply", "-o"));
  const fs::path file = scratch("grid.stl");
  io::AtomicFile out(file);
  EXPECT_THROW(io::makeSampleWriter(OutputFormat::Stl, out), std::logic_error);
}

}  // namespace
}  // namespace shapespline::test
