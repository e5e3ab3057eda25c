// Issue 15 (requirements 1 and 2): welded meshes and curves as one polyline, read back by readers we
// did not write: Python's own parsing of OBJ and of binary PLY (struct), and assimp's `assimp info`
// (Debian assimp-utils) for PLY. Checked: the vertex count is the number of distinct grid points;
// every edge lies in at most two triangles, interior edges in exactly two; a model closed in u and v
// has no boundary edge and Euler characteristic 0; each triangle's winding agrees with its vertices'
// normals and a closed surface's normals point outwards (positive enclosed volume); positions and
// normals equal `shapespline eval` at the vertices' parameters; shards are meshes of their own and
// merge into the unsharded file byte for byte (CPU fp64 and Vulkan fp32); a closed curve is one
// loop with every joint once; `--mesh-layout per-item` keeps the per-patch layout.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

void sampleTo(const ScratchDir& dir, const std::string& modelPath, const std::string& name, const std::string& opts) {
  const CliResult r =
      runCli("sample " + quote(modelPath) + " -o " + quote((dir / name).string()) + " " + opts + " -q", dir.path());
  ASSERT_EQ(r.rc, 0) << name << ": " << r.err;
}

// The mesh readers and checks, in Python: read(path) -> (positions, normals, uvs, triangles, lines).
constexpr const char* kReaders = R"PY(
import struct, sys, json, math

def read_obj(path):
    v, vt, vn, tris, lines = [], [], [], [], []
    for line in open(path):
        t = line.split()
        if not t or t[0].startswith('#'):
            continue
        if t[0] == 'v': v.append(tuple(float(x) for x in t[1:4]))
        elif t[0] == 'vt': vt.append(tuple(float(x) for x in t[1:3]))
        elif t[0] == 'vn': vn.append(tuple(float(x) for x in t[1:4]))
        elif t[0] == 'f':
            idx = [[int(p) for p in c.split('/')] for c in t[1:]]
            assert len(idx) == 3 and all(a == b == c for a, b, c in idx), line
            tris.append(tuple(a - 1 for a, _, _ in idx))
        elif t[0] == 'l':
            lines.append([int(x) - 1 for x in t[1:]])
        else:
            raise AssertionError('unexpected OBJ line ' + line)
    return v, vn, vt, tris, lines

def read_ply(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode().splitlines()
    assert header[1] == 'format binary_little_endian 1.0'
    elements, props = [], None
    for h in header:
        t = h.split()
        if t[0] == 'element':
            elements.append((t[1], int(t[2]), []))
        elif t[0] == 'property':
            elements[-1][2].append(t[1:])
    pos = end
    v, vn, vt, tris, edges = [], [], [], [], []
    for name, count, ps in elements:
        if name == 'vertex':
            fmt = '<' + ''.join('d' if p[0] == 'double' else 'f' for p in ps)
            names = [p[1] for p in ps]
            size = struct.calcsize(fmt)
            for k in range(count):
                rec = dict(zip(names, struct.unpack_from(fmt, data, pos)))
                pos += size
                v.append((rec['x'], rec['y'], rec['z']))
                if 'nx' in rec: vn.append((rec['nx'], rec['ny'], rec['nz']))
                if 's' in rec: vt.append((rec['s'], rec['t']))
        elif name == 'face':
            for k in range(count):
                n, a, b, c = struct.unpack_from('<BIII', data, pos)
                assert n == 3
                pos += 13
                tris.append((a, b, c))
        elif name == 'edge':
            for k in range(count):
                edges.append(struct.unpack_from('<II', data, pos))
                pos += 8
    assert pos == len(data), (pos, len(data))
    lines = []
    if edges:  # consecutive edges of one polyline
        path = [edges[0][0]]
        for a, b in edges:
            assert a == path[-1], 'edges do not chain'
            path.append(b)
        lines = [path]
    return v, vn, vt, tris, lines

def read(path):
    return read_obj(path) if path.endswith('.obj') else read_ply(path)

def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

def check_mesh(path, distinct, closed_u, closed_v):
    v, vn, vt, tris, lines = read(path)
    assert len(v) == distinct, ('vertices', len(v), distinct)
    assert len(vn) == len(v) and len(vt) == len(v)
    used = set(i for t in tris for i in t)
    assert used == set(range(len(v))), 'every vertex is used, no index outside'
    edges = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges.setdefault((min(a, b), max(a, b)), []).append((a, b))
    boundary = 0
    for e, uses in edges.items():
        assert len(uses) <= 2, ('edge in more than two triangles', e)
        if len(uses) == 2:
            assert uses[0] != uses[1], ('neighbours wound inconsistently', e)
        else:
            boundary += 1
    euler = len(v) - len(edges) + len(tris)
    # Winding against the stored normals: every non-degenerate triangle faces its vertices' normals.
    volume, disagree = 0.0, 0
    for t in tris:
        p0, p1, p2 = v[t[0]], v[t[1]], v[t[2]]
        n = cross(sub(p1, p0), sub(p2, p0))
        volume += dot(p0, cross(p1, p2)) / 6
        if math.sqrt(dot(n, n)) < 1e-12:
            continue
        mean = tuple(sum(vn[i][k] for i in t) for k in range(3))
        if dot(n, mean) <= 0: disagree += 1
    assert disagree == 0, ('triangles facing away from their normals', disagree)
    return boundary, euler, volume
)PY";

void python(const ScratchDir& dir, const std::string& body, const std::vector<std::string>& args) {
  if (!fs::exists(kPython)) GTEST_SKIP() << kPython << " is missing (scripts/setup.sh installs it)";
  expectPythonOk(dir, std::string(kReaders) + body, args);
}

// The torus: 8 x 6 patches, closed in u and v; S x S samples per patch give 8 (S-1) x 6 (S-1) points.
TEST(WeldedMesh, ClosedTorusIsWatertightAndFacesOutwards) {
  ScratchDir dir("mesh_ClosedTorusIsWatertightAndFacesOutwards");
  sampleTo(dir, exampleModel("torus_aeb.json"), "t.obj", "--grid 7x5 --device cpu");
  sampleTo(dir, exampleModel("torus_aeb.json"), "t.ply", "--grid 7x5 --device cpu");
  python(dir, R"PY(
for path in sys.argv[1:]:
    boundary, euler, volume = check_mesh(path, 8 * 6 * 6 * 4, True, True)
    assert boundary == 0, ('boundary edges', boundary)
    assert euler == 0, ('Euler characteristic', euler)
    assert volume > 0, ('normals point inwards', volume)
print('OK')
)PY",
         {(dir / "t.obj").string(), (dir / "t.ply").string()});
}

// The same torus with its rows in reverse order: du x dv points inwards, so the writer flips the
// winding and the normals, and says so in the mesh line.
TEST(WeldedMesh, InwardTorusIsReversed) {
  ScratchDir dir("mesh_InwardTorusIsReversed");
  std::string text = readText(exampleModel("torus_aeb.json"));
  const CliResult r = runCaptured(std::string(kPython) + " -c " +
                                      quote("import json,sys; m=json.load(open(sys.argv[1])); m['points']=m['points'][::-1];"
                                            " m['alpha']=m['alpha'][::-1]; json.dump(m, open(sys.argv[2],'w'))") +
                                      " " + quote(exampleModel("torus_aeb.json")) + " " + quote((dir / "inward.json").string()) +
                                      " >" + quote((dir / "_o").string()) + " 2>" + quote((dir / "_e").string()),
                                  dir / "_o", dir / "_e");
  ASSERT_EQ(r.rc, 0) << r.err;
  sampleTo(dir, (dir / "inward.json").string(), "t.obj", "--grid 5 --device cpu");
  EXPECT_TRUE(contains(readText(dir / "t.obj"), "orientation reversed"));
  python(dir, R"PY(
boundary, euler, volume = check_mesh(sys.argv[1], 8 * 6 * 4 * 4, True, True)
assert boundary == 0 and euler == 0 and volume > 0, (boundary, euler, volume)
print('OK')
)PY",
         {(dir / "t.obj").string()});
}

TEST(WeldedMesh, OpenSurfaceHasItsBoundaryOnly) {
  ScratchDir dir("mesh_OpenSurfaceHasItsBoundaryOnly");
  // surface_aeb.json: 4 x 4 patches, open.
  sampleTo(dir, exampleModel("surface_aeb.json"), "s.ply", "--grid 6x4 --device cpu");
  sampleTo(dir, exampleModel("surface_aeb.json"), "s.obj", "--grid 6x4 --device cpu --precision float");
  python(dir, R"PY(
rows, cols = 4 * 5 + 1, 4 * 3 + 1
for path in sys.argv[1:]:
    boundary, euler, volume = check_mesh(path, rows * cols, False, False)
    assert boundary == 2 * (rows - 1) + 2 * (cols - 1), ('boundary', boundary)
    assert euler == 1, ('Euler characteristic of a disc', euler)
print('OK')
)PY",
         {(dir / "s.ply").string(), (dir / "s.obj").string()});
}

// Positions and normals against `shapespline eval` at each vertex's parameter (from its texture
// coordinate: (s, t) over the 4 x 4 patches of surface_aeb.json). fp64 CPU: positions within 1e-12
// of the model's size; normals within 1e-12 where one patch gives the vertex, and within 1e-9 on
// patch boundaries (the normalised mean of the patches' normals, which agree there: C^2) except
// at the alpha = 1 vertex, where the patches' diagonal limits differ and the mean is a convention.
TEST(WeldedMesh, VerticesEqualEval) {
  ScratchDir dir("mesh_VerticesEqualEval");
  sampleTo(dir, exampleModel("surface_aeb.json"), "s.ply", "--grid 5 --device cpu");
  python(dir, R"PY(
import subprocess
v, vn, vt, tris, lines = read_ply(sys.argv[1])
def local(x):  # global parameter in [0, 4] -> (patch, local parameter)
    i = min(int(math.floor(x)), 3)
    return i, x - i
samples = []
for s, t in vt:
    (i, u), (j, w) = local(s * 4), local(t * 4)
    samples.append({"patch": [i, j], "uv": [u, w]})
json.dump({"samples": samples}, open(sys.argv[3], 'w'))
out = subprocess.run([sys.argv[2], 'eval', sys.argv[4], '--at', sys.argv[3], '--device', 'cpu'],
                     capture_output=True, text=True, check=True).stdout
rows = json.loads(out)['samples']
assert len(rows) == len(v)
worst_p, worst_n = 0.0, 0.0
for k, r in enumerate(rows):
    p, n = r['point'], r['normal'] if r['normal'] is not None else r['render_normal']
    worst_p = max(worst_p, max(abs(p[i] - v[k][i]) for i in range(3)))
    s, t = vt[k]
    on_boundary = abs(s * 4 - round(s * 4)) < 1e-12 or abs(t * 4 - round(t * 4)) < 1e-12
    if abs(s * 4 - 2) < 1e-12 and abs(t * 4 - 2) < 1e-12:
        continue  # the alpha = 1 vertex
    tol = 1e-9 if on_boundary else 1e-12
    dn = max(abs(n[i] - vn[k][i]) for i in range(3))
    assert dn <= tol, (k, s, t, n, vn[k])
    worst_n = max(worst_n, dn)
assert worst_p <= 1e-12 * 4, worst_p
print('OK', worst_p, worst_n)
)PY",
         {(dir / "s.ply").string(), SHAPESPLINE_CLI, (dir / "at.json").string(), exampleModel("surface_aeb.json")});
}

void expectShardsMerge(const ScratchDir& dir, const std::string& modelPath, const std::string& ext,
                       const std::string& opts, int shards) {
  sampleTo(dir, modelPath, "whole." + ext, opts);
  std::string list;
  for (int k = 1; k <= shards; ++k) {
    const std::string name = "part" + std::to_string(k) + "." + ext;
    sampleTo(dir, modelPath, name, opts + " --shard " + std::to_string(k) + "/" + std::to_string(shards));
    list += " " + quote((dir / name).string());
  }
  const CliResult m = runCli("merge" + list + " -o " + quote((dir / ("merged." + ext)).string()), dir.path());
  ASSERT_EQ(m.rc, 0) << m.err;
  EXPECT_EQ(readText(dir / ("merged." + ext)), readText(dir / ("whole." + ext))) << modelPath << " " << ext << " " << opts;
}

TEST(WeldedMesh, ShardsAreMeshesAndMergeByteForByte) {
  ScratchDir dir("mesh_ShardsAreMeshesAndMergeByteForByte");
  for (const std::string ext : {"obj", "ply"}) {
    expectShardsMerge(dir, exampleModel("torus_aeb.json"), ext, "--grid 5x4 --device cpu", 5);
    expectShardsMerge(dir, exampleModel("surface_aeb.json"), ext, "--grid 4 --device cpu --precision float", 3);
    expectShardsMerge(dir, exampleModel("butterfly_aeb.json"), ext, "--samples 7 --device cpu", 4);
    expectShardsMerge(dir, exampleModel("open_aeb.json"), ext, "--samples 5 --device cpu", 2);
  }
  // A shard on its own: a mesh whose every vertex is used and every index is in range.
  python(dir, R"PY(
for path in sys.argv[1:]:
    v, vn, vt, tris, lines = read(path)
    used = set(i for t in tris + lines for i in t)
    assert used == set(range(len(v))), path
print('OK')
)PY",
         {(dir / "part1.obj").string(), (dir / "part2.ply").string()});
  // And a surface shard: the torus in 3 parts.
  sampleTo(dir, exampleModel("torus_aeb.json"), "torus2.ply", "--grid 4 --device cpu --shard 2/3");
  python(dir, R"PY(
v, vn, vt, tris, lines = read(sys.argv[1])
assert tris and set(i for t in tris for i in t) == set(range(len(v)))
print('OK')
)PY",
         {(dir / "torus2.ply").string()});
}

TEST(WeldedMesh, GpuFloatShardsMergeByteForByte) {
  if (!vulkanDevice()) GTEST_SKIP() << "no Vulkan device";
  ScratchDir dir("mesh_GpuFloatShardsMergeByteForByte");
  expectShardsMerge(dir, exampleModel("torus_aeb.json"), "ply", "--grid 6 --device vulkan --require-device --precision float", 4);
  expectShardsMerge(dir, exampleModel("surface_aeb.json"), "obj", "--grid 5 --device vulkan --require-device --precision float", 3);
}

TEST(WeldedMesh, ClosedCurveIsOneLoop) {
  ScratchDir dir("mesh_ClosedCurveIsOneLoop");
  // butterfly_aeb.json: a closed curve of 20 spans; open_aeb.json: an open one.
  sampleTo(dir, exampleModel("butterfly_aeb.json"), "c.obj", "--samples 6 --device cpu");
  sampleTo(dir, exampleModel("butterfly_aeb.json"), "c.ply", "--samples 6 --device cpu");
  sampleTo(dir, exampleModel("open_aeb.json"), "o.obj", "--samples 6 --device cpu");
  python(dir, R"PY(
for path in sys.argv[1:3]:
    v, vn, vt, tris, lines = read(path)
    assert len(lines) == 1, ('polylines', len(lines))
    l = lines[0]
    assert len(v) == 20 * 5, len(v)
    assert l[0] == l[-1] and len(l) == len(v) + 1, 'a closed loop'
    assert sorted(l[:-1]) == list(range(len(v))), 'every joint once'
    # Consecutive points are near: the loop follows the curve.
    step = [math.dist(v[a], v[b]) for a, b in zip(l, l[1:])]
    assert max(step) < 10 * (sum(step) / len(step)), max(step)
v, vn, vt, tris, lines = read(sys.argv[3])
assert len(lines) == 1 and lines[0] == list(range(len(v))) and lines[0][0] != lines[0][-1]
print('OK')
)PY",
         {(dir / "c.obj").string(), (dir / "c.ply").string(), (dir / "o.obj").string()});
}

TEST(WeldedMesh, AssimpReadsTheWeldedPly) {
  if (std::system("command -v assimp >/dev/null 2>&1") != 0) GTEST_SKIP() << "assimp-utils missing (scripts/setup.sh)";
  ScratchDir dir("mesh_AssimpReadsTheWeldedPly");
  sampleTo(dir, exampleModel("torus_aeb.json"), "t.ply", "--grid 5 --device cpu");
  sampleTo(dir, exampleModel("torus_aeb.json"), "t.obj", "--grid 5 --device cpu");
  const CliResult r = runCaptured("assimp info " + quote((dir / "t.ply").string()) + " >" + quote((dir / "_o").string()) +
                                      " 2>" + quote((dir / "_e").string()),
                                  dir / "_o", dir / "_e");
  ASSERT_EQ(r.rc, 0) << r.out << r.err;
  // 8 x 6 patches of 5 x 5: 32 x 24 distinct points, 2 x 48 x 16 triangles.
  EXPECT_TRUE(contains(r.out, "Vertices:           768")) << r.out;
  EXPECT_TRUE(contains(r.out, "Faces:              1536")) << r.out;
  EXPECT_TRUE(contains(r.out, "Primitive Types:    triangles")) << r.out;
  // assimp's OBJ importer rebuilds vertices per face corner (its count follows its own joining),
  // so for OBJ only the faces are compared.
  const CliResult o = runCaptured("assimp info " + quote((dir / "t.obj").string()) + " >" + quote((dir / "_o").string()) +
                                      " 2>" + quote((dir / "_e").string()),
                                  dir / "_o", dir / "_e");
  ASSERT_EQ(o.rc, 0) << o.out << o.err;
  EXPECT_TRUE(contains(o.out, "Faces:              1536")) << o.out;
}

TEST(WeldedMesh, PerItemLayoutKeepsEveryPatch) {
  ScratchDir dir("mesh_PerItemLayoutKeepsEveryPatch");
  sampleTo(dir, exampleModel("surface_aeb.json"), "p.obj", "--grid 4 --device cpu --mesh-layout per-item");
  sampleTo(dir, exampleModel("surface_aeb.json"), "p.ply", "--grid 4 --device cpu --mesh-layout per-item");
  python(dir, R"PY(
for path in sys.argv[1:]:
    v, vn, vt, tris, lines = read(path)
    assert len(v) == 16 * 16 and len(tris) == 16 * 18, (len(v), len(tris))
print('OK')
)PY",
         {(dir / "p.obj").string(), (dir / "p.ply").string()});
  const CliResult bad = runCli("sample " + quote(exampleModel("surface_aeb.json")) + " -o x.obj --mesh-layout soup", dir.path());
  EXPECT_EQ(bad.rc, 2);
  EXPECT_TRUE(contains(bad.err, "--mesh-layout")) << bad.err;
  EXPECT_TRUE(contains(bad.err, "welded or per-item")) << bad.err;
  const CliResult raw = runCli("sample " + quote(exampleModel("surface_aeb.json")) + " -o x.f32 --mesh-layout per-item", dir.path());
  EXPECT_EQ(raw.rc, 2);
  EXPECT_FALSE(fs::exists(dir / "x.obj"));
  EXPECT_FALSE(fs::exists(dir / "x.f32"));
}


// Welded shards that do not fit together are refused (exit 2) with nothing written.
TEST(WeldedMesh, MismatchedWeldedShardsAreRefused) {
  ScratchDir dir("mesh_mismatch");
  for (const std::string ext : {"obj", "ply"}) {
    sampleTo(dir, exampleModel("torus_aeb.json"), "a1." + ext, "--grid 4 --device cpu --shard 1/2");
    sampleTo(dir, exampleModel("torus_aeb.json"), "a2." + ext, "--grid 4 --device cpu --shard 2/2");
    sampleTo(dir, exampleModel("torus_aeb.json"), "p2." + ext, "--grid 4 --device cpu --shard 2/2 --mesh-layout per-item");
    auto merge = [&](const std::string& second) {
      return runCli("merge " + quote((dir / ("a1." + ext)).string()) + " " + quote((dir / second).string()) + " -o " +
                        quote((dir / ("m." + ext)).string()),
                    dir.path());
    };
    // A per-item shard beside a welded one: another job (the fingerprint covers the layout).
    const CliResult mixed = merge("p2." + ext);
    EXPECT_EQ(mixed.rc, 2) << mixed.err;
    EXPECT_TRUE(contains(mixed.err, "SHARD[2]")) << mixed.err;
    // A mesh line edited to another grid of items.
    std::string text = readText(dir / ("a2." + ext));
    const size_t at = text.find("items 8x6");
    ASSERT_NE(at, std::string::npos);
    writeText(dir / ("b2." + ext), text.substr(0, at) + "items 6x8" + text.substr(at + 9));
    const CliResult edited = merge("b2." + ext);
    EXPECT_EQ(edited.rc, 2) << edited.err;
    EXPECT_TRUE(contains(edited.err, "SHARD[2]")) << edited.err;  // its counts or its mesh layout
    writeText(dir / ("c2." + ext), text.substr(0, at) + "items 4x12" + text.substr(at + 9));
    EXPECT_EQ(merge("c2." + ext).rc, 2);
    writeText(dir / ("d2." + ext), text.substr(0, at) + "items 8x7" + text.substr(at + 9));
    const CliResult wrongCount = merge("d2." + ext);
    EXPECT_EQ(wrongCount.rc, 2) << wrongCount.err;
    EXPECT_FALSE(fs::exists(dir / ("m." + ext)));
  }
}

}  // namespace
}  // namespace shapespline::test
