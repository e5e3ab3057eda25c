// Issue 15 (requirements 1-3) for `sample -o OUT.glb` and `-o OUT.gltf` (+ OUT.bin), checked by
// readers we did not write:
//  * the Khronos glTF validator (npm gltf-validator, pinned in tests/tools/gltf and installed by
//    scripts/setup.sh): zero errors and zero warnings (infos and hints are printed);
//  * Debian's assimp (`assimp info -r`, raw import): the vertex and face counts;
//  * Debian's /usr/bin/python3 with struct/json/numpy reading the GLB chunks or the .gltf + .bin:
//    the vertex count is the number of distinct grid points; every eval sample of the grid
//    (`shapespline eval` at the same parameters) lies on a vertex within the fp32 rounding of the
//    re-centred positions, and every vertex is one of them; the normals are the normalised sums of
//    the eval normals of their samples and agree with the winding (counter-clockwise front faces);
//    the texture coordinates are (U, 1 - V) normalised; surfaces have each interior edge in
//    exactly two triangles, closed ones (a torus) none on a boundary, Euler characteristic 0 and
//    outward normals; curves are one LINE_STRIP, or a LINE_LOOP without a repeated vertex;
//  * refused jobs (--shard, more than kMaxGltfVertices vertices) exit 2 and leave no file.
#include "cli_runner.h"
#include "output_checks.h"

#include <shapespline/io/sample_writer.h>
#include <shapespline/io/welded_mesh.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Why the external readers cannot run here (CI installs all of them: scripts/setup.sh), or "".
std::string readersMissing() {
  for (const std::string& why : {gltfValidatorMissing(), assimpMissing(), pythonNumpyMissing()}) {
    if (!why.empty()) return why;
  }
  return "";
}

#define REQUIRE_READERS()                        \
  do {                                           \
    const std::string why_ = readersMissing();   \
    if (!why_.empty()) GTEST_SKIP() << why_;     \
  } while (0)

// An α-EB torus (closed in u and v): 6 x 8 points, u around the z axis, v around the tube. With
// `inward`, v runs the other way, so du x dv points into the tube and the writer must flip.
std::string writeTorus(const ScratchDir& dir, const std::string& name, bool inward) {
  const int nu = 6, nv = 8;
  const double R = 3.0, r = 1.0;
  json points = json::array(), alpha = json::array();
  for (int i = 0; i < nu; ++i) {
    json row = json::array(), arow = json::array();
    for (int j = 0; j < nv; ++j) {
      const double a = 2 * M_PI * i / nu, b = (inward ? -1 : 1) * 2 * M_PI * j / nv;
      row.push_back({(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b)});
      arow.push_back(0.5);
    }
    points.push_back(row);
    alpha.push_back(arow);
  }
  const json m = {{"kind", "surface"}, {"construction", "alpha_eb"}, {"degree", 5}, {"lambda", 0},
                  {"closed", {true, true}}, {"points", points}, {"alpha", alpha}};
  const fs::path p = dir / name;
  writeText(p, m.dump());
  return p.string();
}

// argv: file.glb|file.gltf, eval.json, expected vertices, closedU, closedV, torus (outward check).
// Prints "OK" and one JSON line of what it found.
constexpr const char* kGltfCheck = R"PY(
import json, os, struct, sys, urllib.parse
import numpy as np
path, evalpath = sys.argv[1], sys.argv[2]
want_vertices, closed_u, closed_v, torus = int(sys.argv[3]), sys.argv[4] == "1", sys.argv[5] == "1", sys.argv[6] == "1"
raw = open(path, "rb").read()
if path.endswith(".glb"):
    magic, version, length = struct.unpack_from("<4sII", raw, 0)
    assert magic == b"glTF" and version == 2 and length == len(raw), (magic, version, length, len(raw))
    jlen, jtype = struct.unpack_from("<II", raw, 12)
    assert jtype == 0x4E4F534A and jlen % 4 == 0
    doc = json.loads(raw[20:20 + jlen])
    blen, btype = struct.unpack_from("<II", raw, 20 + jlen)
    assert btype == 0x004E4942 and blen % 4 == 0
    binary = raw[28 + jlen:28 + jlen + blen]
    assert 28 + jlen + blen == len(raw)
    assert "uri" not in doc["buffers"][0]
    assert len(binary) - doc["buffers"][0]["byteLength"] in range(4)
else:
    doc = json.loads(raw)
    uri = doc["buffers"][0]["uri"]
    assert not uri.startswith("data:"), "the buffer is embedded"
    binary = open(os.path.join(os.path.dirname(path), urllib.parse.unquote(uri)), "rb").read()
    assert len(binary) == doc["buffers"][0]["byteLength"]
assert doc["asset"]["version"] == "2.0"
assert doc["asset"]["generator"].startswith("shapespline "), doc["asset"]
assert len(doc["buffers"]) == 1 and len(doc["meshes"]) == 1 and len(doc["meshes"][0]["primitives"]) == 1
extras = doc["meshes"][0]["extras"]
for key in ("tool_version", "model_file", "construction", "device", "computed_precision", "grid"):
    assert key in extras, (key, extras)
assert doc["asset"]["generator"] == "shapespline " + extras["tool_version"]

def accessor(i):
    a = doc["accessors"][i]
    v = doc["bufferViews"][a["bufferView"]]
    dt = {5126: "<f4", 5125: "<u4", 5123: "<u2"}[a["componentType"]]
    n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
    start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    assert start + a["count"] * n * np.dtype(dt).itemsize <= v.get("byteOffset", 0) + v["byteLength"]
    x = np.frombuffer(binary, dtype=dt, count=a["count"] * n, offset=start)
    return a, v, (x.reshape(a["count"], n) if n > 1 else x)

prim = doc["meshes"][0]["primitives"][0]
pa, pv, P32 = accessor(prim["attributes"]["POSITION"])
assert pv["target"] == 34962
assert pa["min"] == [float(x) for x in P32.min(axis=0)] and pa["max"] == [float(x) for x in P32.max(axis=0)]
P = P32.astype(np.float64)
T = np.array(doc["nodes"][doc["scenes"][doc.get("scene", 0)]["nodes"][0]]["translation"], dtype=np.float64)
X = P + T
V = P.shape[0]
assert V == want_vertices, (V, want_vertices)
ia, iv, idx = accessor(prim["indices"])
assert iv["target"] == 34963
assert ia["componentType"] == (5123 if V <= 65535 else 5125)
idx = idx.astype(np.int64)
assert idx.min() >= 0 and idx.max() < V
mode = prim.get("mode", 4)
surface = "NORMAL" in prim["attributes"]

ev = json.load(open(evalpath))["samples"]
E = np.array([s["point"] + [0.0] * (3 - len(s["point"])) for s in ev], dtype=np.float64)
# fp32 rounding of the re-centred positions (half an ulp of the largest stored magnitude per axis),
# plus the fp64 sum with the translation.
tol = 2.0 ** -24 * np.abs(P).max(axis=0) + 4e-16 * (np.abs(T) + np.abs(P).max(axis=0)) + 1e-300
match = []
for e in E:
    d = np.abs(X - e)
    ok = np.nonzero((d <= tol).all(axis=1))[0]
    assert len(ok) >= 1, ("no vertex at eval point", e.tolist(), d.min(axis=0).tolist(), tol.tolist())
    match.append(int(ok[np.argmin(d[ok].sum(axis=1))]))
match = np.array(match)
assert set(match.tolist()) == set(range(V)), "a vertex is no eval sample"
err = np.abs(X[match] - E).max(axis=0)

result = {"vertices": V, "indices": int(idx.size), "mode": mode, "max_error": err.tolist(), "tolerance": tol.tolist(),
          "translation": T.tolist(), "extras_keys": sorted(extras)}
if surface:
    assert mode == 4 and idx.size % 3 == 0
    na, nv_, N = accessor(prim["attributes"]["NORMAL"])
    ta, tv, UV = accessor(prim["attributes"]["TEXCOORD_0"])
    N = N.astype(np.float64)
    assert np.all(np.abs(np.linalg.norm(N, axis=1) - 1) < 1e-6)
    # Normal of a vertex: the normalised sum of its samples' eval normals (at an alpha = 1 vertex,
    # where eval's "normal" is null, its "render_normal": the patch's diagonal limit), up to one
    # sign for all.
    S = np.zeros((V, 3))
    singular = 0
    for j, k in enumerate(match):
        n = ev[j]["normal"]
        if n is None:
            n = ev[j]["render_normal"]
            singular += 1
        S[k] += n
    S /= np.linalg.norm(S, axis=1)[:, None]
    dots = np.einsum("ij,ij->i", N, S)
    sign = 1.0 if dots[0] > 0 else -1.0
    assert np.all(sign * dots > 1 - 1e-5), ("normals differ from eval", float((sign * dots).min()))
    # Texture coordinates: (U, 1 - V) normalised over the model; a seam vertex has its first sample's.
    U = np.array([s["UV"] for s in ev])
    lo, hi = U.min(axis=0), U.max(axis=0)
    st = (U - lo) / (hi - lo)
    want = np.stack([st[:, 0], 1 - st[:, 1]], axis=1)
    good = np.zeros(V, dtype=bool)
    for j, k in enumerate(match):
        if np.all(np.abs(UV[k] - want[j]) <= 1e-6):
            good[k] = True
    assert good.all(), "texture coordinates differ from (U, 1 - V)"
    tri = idx.reshape(-1, 3)
    assert len(tri) > 0
    assert np.all((tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2]))
    # Winding: counter-clockwise seen from the side the normals point to.
    g = np.cross(P[tri[:, 1]] - P[tri[:, 0]], P[tri[:, 2]] - P[tri[:, 0]])
    nsum = N[tri[:, 0]] + N[tri[:, 1]] + N[tri[:, 2]]
    area = np.linalg.norm(g, axis=1)
    big = area > 1e-9 * area.max()
    wrong = int(np.sum(np.einsum("ij,ij->i", g, nsum)[big] <= 0))
    assert wrong == 0, (wrong, "triangles wound against their normals")
    # Topology: every directed edge once (consistent orientation), every undirected edge in <= 2
    # triangles; boundary edges only along open directions.
    directed = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    keys = directed[:, 0] * V + directed[:, 1]
    assert len(np.unique(keys)) == len(keys), "a directed edge is used twice"
    und = np.sort(directed, axis=1)
    _, counts = np.unique(und[:, 0] * V + und[:, 1], return_counts=True)
    assert counts.max() <= 2
    boundary = int(np.sum(counts == 1))
    E_ = len(counts)
    euler = V - E_ + len(tri)
    result.update({"singular_samples": singular, "triangles": len(tri), "edges": E_, "boundary_edges": boundary, "euler": euler})
    if closed_u and closed_v:
        assert boundary == 0 and euler == 0, (boundary, euler)
    if not closed_u and not closed_v:
        assert boundary > 0 and euler == 1, (boundary, euler)  # a disk
    if torus:
        # Outward: away from the core circle (radius 3 about the z axis, through the origin).
        core = X.copy()
        core[:, 2] = 0
        core *= (3.0 / np.linalg.norm(core, axis=1))[:, None]
        out = np.einsum("ij,ij->i", N, X - core)
        assert np.all(out > 0), ("normals point inwards", int(np.sum(out <= 0)))
else:
    assert set(prim["attributes"]) == {"POSITION"}
    order = [int(k) for i, k in enumerate(match) if i == 0 or k != match[i - 1]]
    seq = idx.tolist()
    if closed_u:
        assert mode == 2, mode
        assert len(seq) == V and len(set(seq)) == V
        assert order == seq + [seq[0]], "the loop does not follow the curve"
    else:
        assert mode == 3, mode
        assert order == seq and len(set(seq)) == V
print("OK")
print(json.dumps(result))
)PY";

struct Job {
  std::string model;  // path
  std::string opts;
  bool closedU = false, closedV = false, torus = false;
};

// Number of distinct grid points of the job, from the raw sidecar's item grid (io/welded_mesh.h).
uint64_t distinctPoints(const json& side, const Job& job) {
  const json& items = side.at("items");
  const uint64_t itemsV = items.at("items_v").get<uint64_t>();
  const uint64_t patchesU = items.at("total").get<uint64_t>() / itemsV;
  const int su = side.at("grid").at("samples_u").get<int>(), sv = side.at("grid").at("samples_v").get<int>();
  const io::WeldGrid grid(patchesU, itemsV, su, sv, job.closedU, job.closedV);
  // And by hand: rows x columns of distinct samples.
  const uint64_t rows = patchesU * static_cast<uint64_t>(su - 1) + (job.closedU ? 0 : 1);
  const uint64_t cols = sv == 1 ? 1 : itemsV * static_cast<uint64_t>(sv - 1) + (job.closedV ? 0 : 1);
  EXPECT_EQ(grid.pointCount(), rows * cols);
  return grid.pointCount();
}

// The eval samples of every grid sample of the job (item order, then a, then b).
json evalSamples(const json& side) {
  const json& items = side.at("items");
  const int su = side.at("grid").at("samples_u").get<int>(), sv = side.at("grid").at("samples_v").get<int>();
  const bool surface = side.at("kind") == "surface";
  json samples = json::array();
  for (const auto& i : items.at("spans_u")) {
    for (const auto& j : items.at("spans_v")) {
      for (int a = 0; a < su; ++a) {
        for (int b = 0; b < sv; ++b) {
          const double u = static_cast<double>(a) / (su - 1);
          if (surface) {
            samples.push_back({{"patch", {i, j}}, {"uv", {u, static_cast<double>(b) / (sv - 1)}}});
          } else {
            samples.push_back({{"span", i}, {"t", u}});
          }
        }
      }
    }
  }
  return json{{"samples", samples}};
}

// Validator: exit 0 means no errors and no warnings; prints the summary and any infos/hints.
void validate(const fs::path& file) {
  const GltfValidation v = validateGltf(file);
  ASSERT_GE(v.errors, 0) << v.report;
  EXPECT_EQ(v.rc, 0) << v.report.substr(0, 4000);
  EXPECT_EQ(v.errors, 0) << v.report.substr(0, 4000);
  EXPECT_EQ(v.warnings, 0) << v.report.substr(0, 4000);
  // Infos and hints are allowed; say which.
  std::string notes;
  std::istringstream lines(v.report);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("info: ", 0) == 0 || line.rfind("hint: ", 0) == 0) notes += "  " + line + "\n";
    if (line.rfind("{", 0) == 0) break;
  }
  std::cout << "[validator] " << file.filename().string() << ": errors 0 warnings 0 infos " << v.infos << " hints "
            << v.hints << "\n"
            << notes;
}

// `assimp info -r` (no post-processing): one mesh with the expected vertices and faces.
void assimpCounts(const ScratchDir& dir, const fs::path& file, uint64_t vertices, uint64_t faces) {
  const CliResult a = runShell("assimp info " + quote(file.string()) + " -r", dir.path());
  ASSERT_EQ(a.rc, 0) << a.out << a.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(a.out, m, std::regex("Vertices:\\s+(\\d+)"))) << a.out;
  EXPECT_EQ(std::stoull(m[1]), vertices) << a.out;
  ASSERT_TRUE(std::regex_search(a.out, m, std::regex("Faces:\\s+(\\d+)"))) << a.out;
  EXPECT_EQ(std::stoull(m[1]), faces) << a.out;
  EXPECT_TRUE(std::regex_search(a.out, std::regex("Meshes:\\s+1\\b"))) << a.out;
}

void checkJob(const ScratchDir& dir, const std::string& stem, const Job& job) {
  SCOPED_TRACE(job.model + " " + job.opts);
  const std::string common = " " + job.opts + " --device cpu -q";
  // The raw output's sidecar names the item grid; eval at every grid sample is the reference.
  const fs::path raw = dir / (stem + ".f64");
  CliResult r = runCli("sample " + quote(job.model) + " -o " + quote(raw.string()) + common, dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const json side = json::parse(readText(raw.string() + ".json"));
  const bool surface = side.at("kind") == "surface";
  const uint64_t vertices = distinctPoints(side, job);
  writeText(dir / (stem + "_at.json"), evalSamples(side).dump());
  r = runCli("eval " + quote(job.model) + " --at " + quote((dir / (stem + "_at.json")).string()) + " --device cpu -q",
             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  writeText(dir / (stem + "_eval.json"), r.out);

  for (const char* ext : {".glb", ".gltf"}) {
    SCOPED_TRACE(ext);
    const fs::path file = dir / (stem + ext);
    r = runCli("sample " + quote(job.model) + " -o " + quote(file.string()) + common, dir.path());
    ASSERT_EQ(r.rc, 0) << r.err;
    const fs::path bin = dir / (stem + ".bin");
    EXPECT_EQ(fs::exists(bin), std::string(ext) == ".gltf") << "a .gltf has its .bin, a .glb stands alone";
    validate(file);

    writeText(dir / "check.py", kGltfCheck);
    const CliResult py = runShell(std::string(kPython) + " " + quote((dir / "check.py").string()) + " " +
                                      quote(file.string()) + " " + quote((dir / (stem + "_eval.json")).string()) +
                                      " " + std::to_string(vertices) + (job.closedU ? " 1" : " 0") +
                                      (job.closedV ? " 1" : " 0") + (job.torus ? " 1" : " 0"),
                                  dir.path());
    ASSERT_EQ(py.rc, 0) << py.out << py.err;
    ASSERT_TRUE(contains(py.out, "OK\n")) << py.out << py.err;
    const json found = json::parse(py.out.substr(py.out.find("OK\n") + 3));
    EXPECT_EQ(found.at("vertices").get<uint64_t>(), vertices);
    std::cout << "[python] " << file.filename().string() << ": " << found.dump() << "\n";

    // assimp: triangles for surfaces; a line strip/loop becomes line segments.
    const uint64_t indices = found.at("indices").get<uint64_t>();
    const uint64_t faces = surface ? indices / 3 : (job.closedU ? indices : indices - 1);
    assimpCounts(dir, file, vertices, faces);
    if (surface) {
      const int su = side.at("grid").at("samples_u").get<int>(), sv = side.at("grid").at("samples_v").get<int>();
      EXPECT_EQ(faces, side.at("counts").at("items").get<uint64_t>() * 2 * (su - 1) * (sv - 1));
    }
  }
}

// surface_aeb.json moved far from the origin: fp32 coordinates there would keep about 0.1 of
// absolute precision; re-centred, the positions keep the digits of the model's own size.
std::string writeShifted(const ScratchDir& dir, const std::string& name) {
  json m = json::parse(readText(examplesDir() + "/surface_aeb.json"));
  for (auto& row : m.at("points"))
    for (auto& p : row) {
      p[0] = p[0].get<double>() + 1.0e6;
      p[1] = p[1].get<double>() - 2.5e6;
      p[2] = p[2].get<double>() + 3.0e5;
    }
  const fs::path path = dir / name;
  writeText(path, m.dump());
  return path.string();
}

TEST(GltfOutput, SurfacesAreValidWeldedMeshesThatEqualEval) {
  REQUIRE_READERS();
  ScratchDir dir("gltf_surfaces");
  checkJob(dir, "far", {writeShifted(dir, "far.json"), "--grid 3x4", false, false, false});
  checkJob(dir, "aeb", {examplesDir() + "/surface_aeb.json", "--grid 4x5", false, false, false});
  checkJob(dir, "aeb_float", {examplesDir() + "/surface_aeb.json", "--grid 3 --precision float", false, false, false});
  checkJob(dir, "bspline", {examplesDir() + "/bspline_surface.json", "--grid 3x4", false, false, false});
}

TEST(GltfOutput, ClosedTorusIsWatertightWithOutwardNormals) {
  REQUIRE_READERS();
  ScratchDir dir("gltf_torus");
  checkJob(dir, "torus", {writeTorus(dir, "torus.json", false), "--grid 4x3", true, true, true});
  checkJob(dir, "torus_in", {writeTorus(dir, "torus_in.json", true), "--grid 3x4", true, true, true});
  // The example torus: alpha = 1 at one vertex (its normal is the mean of the patches' limits).
  checkJob(dir, "example", {examplesDir() + "/torus_aeb.json", "--grid 3", true, true, true});
}

TEST(GltfOutput, CurvesAreLineStripsAndLoops) {
  REQUIRE_READERS();
  ScratchDir dir("gltf_curves");
  checkJob(dir, "open", {examplesDir() + "/open_aeb.json", "--samples 7", false, false, false});
  checkJob(dir, "closed", {examplesDir() + "/butterfly_aeb.json", "--samples 5", true, false, false});
}

// A .gltf and its .bin are one output set: when either rename fails, both targets keep their
// previous contents (or stay absent) and no temporary file is left.
TEST(GltfOutput, GltfAndBinAppearTogether) {
  ScratchDir dir("gltf_set");
  const std::string m = quote(examplesDir() + "/surface_aeb.json");
  const fs::path gltf = dir / "x.gltf", bin = dir / "x.bin";
  const CliResult r = runCli("sample " + m + " -o " + quote(gltf.string()) + " --grid 3 --device cpu -q", dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const std::string oldGltf = readText(gltf), oldBin = readText(bin);
  for (const char* fault : {"rename:1", "rename:2"}) {
    SCOPED_TRACE(fault);
    for (const fs::path& out : {gltf, dir / "fresh.gltf"}) {
      const CliResult f = runShell(std::string("SHAPESPLINE_IO_FAULT=") + fault + " " + quote(SHAPESPLINE_CLI) +
                                       " sample " + m + " -o " + quote(out.string()) + " --grid 4 --device cpu -q",
                                   dir.path());
      EXPECT_EQ(f.rc, 3) << f.err;
    }
    EXPECT_EQ(readText(gltf), oldGltf);
    EXPECT_EQ(readText(bin), oldBin);
    EXPECT_FALSE(fs::exists(dir / "fresh.gltf"));
    EXPECT_FALSE(fs::exists(dir / "fresh.bin"));
  }
  for (const auto& e : dir.entries()) EXPECT_TRUE(e == "x.gltf" || e == "x.bin") << e;
}

TEST(GltfOutput, ShardsAndOversizedJobsAreRefusedBeforeAnyFile) {
  ScratchDir dir("gltf_refused");
  const std::string m = quote(examplesDir() + "/surface_aeb.json");
  for (const char* ext : {".glb", ".gltf"}) {
    const fs::path out = dir / (std::string("x") + ext);
    const CliResult s = runCli("sample " + m + " -o " + quote(out.string()) + " --shard 1/2 --device cpu -q", dir.path());
    EXPECT_EQ(s.rc, 2) << s.err;
    EXPECT_TRUE(contains(s.err, "--shard")) << s.err;
    EXPECT_TRUE(contains(s.err, ".ply")) << s.err;
    // surface_aeb has 4 x 4 patches: 2049 samples per direction give 8193^2 > 2^24 vertices.
    const CliResult big = runCli("sample " + m + " -o " + quote(out.string()) + " --grid 2049 --device cpu -q", dir.path());
    EXPECT_EQ(big.rc, 2) << big.err;
    EXPECT_TRUE(contains(big.err, "--grid")) << big.err;
    EXPECT_TRUE(contains(big.err, std::to_string(8193ull * 8193ull))) << big.err;
    EXPECT_TRUE(contains(big.err, std::to_string(io::kMaxGltfVertices))) << big.err;
    EXPECT_TRUE(contains(big.err, ".npy")) << big.err;
    // Just past the cap: 4097^2 = 16785409 > 2^24 = 16777216.
    const CliResult edge = runCli("sample " + m + " -o " + quote(out.string()) + " --grid 1025 --device cpu -q", dir.path());
    EXPECT_EQ(edge.rc, 2) << edge.err;
    EXPECT_TRUE(dir.entries().empty()) << "a refused job leaves no file";
  }
  // merge does not take glTF files.
  const CliResult mg = runCli("merge -o " + quote((dir / "m.glb").string()) + " " + quote((dir / "a.glb").string()),
                              dir.path());
  EXPECT_EQ(mg.rc, 2) << mg.err;
  EXPECT_FALSE(fs::exists(dir / "m.glb"));
}

}  // namespace
}  // namespace shapespline::test
