// `sample` end to end: every output format parsed back and compared with the core evaluators,
// atomic output, shards that concatenate/merge into the whole job.
#include "cli_runner.h"
#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>
#include "support/tolerances.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace shapespline::test {
namespace {

Curve loadCurve(const std::string& name) {
  return Curve::create(std::get<CurveModel>(io::loadModelFile(examplesDir() + "/" + name)));
}
Surface loadSurface(const std::string& name) {
  return Surface::create(std::get<SurfaceModel>(io::loadModelFile(examplesDir() + "/" + name)));
}

double extent(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

void expectNear(const glm::dvec3& expected, const glm::dvec3& actual, double tol, const std::string& what) {
  const double err = glm::length(expected - actual);
  EXPECT_LE(err, tol) << what << ": expected (" << expected.x << ", " << expected.y << ", " << expected.z
                      << ") got (" << actual.x << ", " << actual.y << ", " << actual.z << ")";
}

struct Obj {
  std::vector<glm::dvec3> v, vn;
  std::vector<std::pair<double, double>> vt;
  std::vector<std::vector<long long>> faces, lines;
};

Obj parseObj(const std::string& text) {
  Obj o;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v" || tag == "vn") {
      glm::dvec3 p;
      ls >> p.x >> p.y >> p.z;
      (tag == "v" ? o.v : o.vn).push_back(p);
    } else if (tag == "vt") {
      double a, b;
      ls >> a >> b;
      o.vt.emplace_back(a, b);
    } else if (tag == "f" || tag == "l") {
      std::vector<long long> idx;
      std::string tok;
      while (ls >> tok) {
        long long i = std::stoll(tok.substr(0, tok.find('/')));
        idx.push_back(i < 0 ? static_cast<long long>(o.v.size()) + i + 1 : i);  // relative -> absolute
      }
      (tag == "f" ? o.faces : o.lines).push_back(idx);
    }
  }
  return o;
}

TEST(CliSample, ObjCurveMatchesCore) {
  ScratchDir dir("obj_curve");
  const CliResult r = runCli("sample " + quote(examplesDir() + "/open_aeb.json") + " -o " +
                                 quote((dir / "c.obj").string()) + " --samples 9 --device cpu --mesh-layout per-item",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const Curve curve = loadCurve("open_aeb.json");
  const Obj o = parseObj(readText(dir / "c.obj"));
  const auto spans = curveGridItems(curve);
  ASSERT_EQ(o.v.size(), spans.size() * 9);
  ASSERT_EQ(o.lines.size(), spans.size());
  const double tol = kFp64Rel * extent(curve.model().points);
  for (size_t k = 0; k < spans.size(); ++k) {
    ASSERT_EQ(o.lines[k].size(), 9u);
    for (int s = 0; s < 9; ++s) {
      const auto& p = o.v[static_cast<size_t>(o.lines[k][static_cast<size_t>(s)] - 1)];
      expectNear(curve.evaluate(spans[k], s / 8.0).point, p, tol, "span " + std::to_string(spans[k]) + " s " + std::to_string(s));
    }
  }
}

TEST(CliSample, ObjSurfaceMeshWithNormalsAndUv) {
  ScratchDir dir("obj_surface");
  const CliResult r = runCli("sample " + quote(examplesDir() + "/surface_aeb.json") + " -o " +
                                 quote((dir / "s.obj").string()) + " --grid 5x4 --device cpu --mesh-layout per-item",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const Surface surface = loadSurface("surface_aeb.json");
  const auto items = surfaceGridItems(surface);
  const Obj o = parseObj(readText(dir / "s.obj"));
  ASSERT_EQ(o.v.size(), items.size() * 20);
  ASSERT_EQ(o.vn.size(), o.v.size());
  ASSERT_EQ(o.vt.size(), o.v.size());
  ASSERT_EQ(o.faces.size(), items.size() * 2 * 4 * 3);
  const double tol = kFp64Rel * extent(surface.controlPoints());
  for (size_t k = 0; k < items.size(); ++k) {
    for (int a = 0; a < 5; ++a) {
      for (int b = 0; b < 4; ++b) {
        const size_t idx = k * 20 + static_cast<size_t>(a * 4 + b);
        const SurfacePoint sp = surface.evaluate(items[k].first, items[k].second, a / 4.0, b / 3.0);
        expectNear(sp.point, o.v[idx], tol, "point");
        expectNear(sp.normal, o.vn[idx], 1e-12, "normal");
        EXPECT_GE(o.vt[idx].first, 0.0);
        EXPECT_LE(o.vt[idx].first, 1.0);
      }
    }
  }
  for (const auto& f : o.faces) {
    ASSERT_EQ(f.size(), 3u);
    // Triangles wind counter-clockwise seen from the normal.
    const glm::dvec3 n = glm::cross(o.v[f[1] - 1] - o.v[f[0] - 1], o.v[f[2] - 1] - o.v[f[0] - 1]);
    EXPECT_GT(glm::dot(n, o.vn[f[0] - 1]), 0.0);
  }
}

struct Ply {
  size_t vertices = 0, faces = 0, edges = 0;
  std::vector<std::string> props;
  bool dbl = true;
  std::vector<double> values;  // vertices * props
  std::vector<std::array<uint32_t, 3>> tris;
  std::vector<std::array<uint32_t, 2>> edgeList;
};

Ply parsePly(const std::string& all) {
  Ply p;
  const size_t end = all.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  std::istringstream in(all.substr(0, end));
  std::string line, element;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format") {
      EXPECT_NE(line.find("binary_little_endian 1.0"), std::string::npos);
    }
    if (w == "element") {
      size_t n;
      ls >> element >> n;
      (element == "vertex" ? p.vertices : element == "face" ? p.faces : p.edges) = n;
    } else if (w == "property" && element == "vertex") {
      std::string type, name;
      ls >> type >> name;
      p.dbl = type == "double";
      p.props.push_back(name);
    }
  }
  const char* c = all.data() + end + 11;
  const size_t sz = p.dbl ? 8 : 4;
  EXPECT_EQ(all.size() - (end + 11), p.vertices * p.props.size() * sz + p.faces * 13 + p.edges * 8);
  for (size_t i = 0; i < p.vertices * p.props.size(); ++i, c += sz) {
    if (p.dbl) {
      double d;
      std::memcpy(&d, c, 8);
      p.values.push_back(d);
    } else {
      float f;
      std::memcpy(&f, c, 4);
      p.values.push_back(f);
    }
  }
  for (size_t i = 0; i < p.faces; ++i, c += 13) {
    EXPECT_EQ(c[0], 3);
    std::array<uint32_t, 3> t;
    std::memcpy(t.data(), c + 1, 12);
    p.tris.push_back(t);
  }
  for (size_t i = 0; i < p.edges; ++i, c += 8) {
    std::array<uint32_t, 2> e;
    std::memcpy(e.data(), c, 8);
    p.edgeList.push_back(e);
  }
  return p;
}

TEST(CliSample, PlySurfaceBinaryMatchesCore) {
  ScratchDir dir("ply_surface");
  const CliResult r = runCli("sample " + quote(examplesDir() + "/surface_aeb.json") + " -o " +
                                 quote((dir / "s.ply").string()) + " --grid 3x4 --device cpu --derivatives --mesh-layout per-item",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const Surface surface = loadSurface("surface_aeb.json");
  const auto items = surfaceGridItems(surface);
  const Ply p = parsePly(readText(dir / "s.ply"));
  ASSERT_EQ(p.vertices, items.size() * 12);
  ASSERT_EQ(p.faces, items.size() * 2 * 2 * 3);
  ASSERT_GE(p.props.size(), 8u + 15u);
  EXPECT_EQ(p.props[3], "nx");
  EXPECT_EQ(p.props[6], "s");
  EXPECT_EQ(p.props[8], "du_x");
  const size_t np = p.props.size();
  const double tol = kFp64Rel * extent(surface.controlPoints());
  for (size_t k = 0; k < items.size(); ++k) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 4; ++b) {
        const size_t v = k * 12 + static_cast<size_t>(a * 4 + b);
        const double* x = &p.values[v * np];
        const SurfacePoint sp = surface.evaluate(items[k].first, items[k].second, a / 2.0, b / 3.0);
        expectNear(sp.point, {x[0], x[1], x[2]}, tol, "point");
        expectNear(sp.normal, {x[3], x[4], x[5]}, 1e-12, "normal");
        expectNear(sp.du, {x[8], x[9], x[10]}, tol * 10, "du");
      }
    }
  }
  for (const auto& t : p.tris) {
    for (uint32_t i : t) EXPECT_LT(i, p.vertices);
  }
}

TEST(CliSample, CsvCurveDerivativesMatchCore) {
  ScratchDir dir("csv_curve");
  const CliResult r = runCli("sample " + quote(examplesDir() + "/gubp_curve.json") + " -o " +
                                 quote((dir / "c.csv").string()) + " --samples 5 --derivatives --device cpu -q",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const Curve curve = loadCurve("gubp_curve.json");
  std::istringstream in(readText(dir / "c.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "span,t,u,x,y,d1_x,d1_y,d2_x,d2_y");
  size_t rows = 0;
  const double tol = kFp64Rel * extent(curve.model().points) * 100;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::istringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 9u);
    const CurvePoint cp = curve.evaluate(static_cast<int>(v[0]), v[1]);
    expectNear(cp.point, {v[3], v[4], 0}, tol, "point");
    expectNear(cp.d1, {v[5], v[6], 0}, tol, "d1");
    expectNear(cp.d2, {v[7], v[8], 0}, tol, "d2");
    EXPECT_NEAR(v[2], curve.parameterOf(static_cast<int>(v[0]), v[1]), 1e-12);
    ++rows;
  }
  EXPECT_EQ(rows, curveGridItems(curve).size() * 5);
}

std::vector<char> readBytes(const std::filesystem::path& p) {
  const std::string s = readText(p);
  return {s.begin(), s.end()};
}

TEST(CliSample, RawWithSidecarAndShardsConcatenate) {
  ScratchDir dir("raw_shards");
  const std::string model = quote(examplesDir() + "/butterfly_aeb.json");
  ASSERT_EQ(runCli("sample " + model + " -o " + quote((dir / "all.f64").string()) +
                       " --samples 7 --derivatives --device cpu -q",
                   dir.path()).rc, 0);
  const json side = json::parse(readText(dir / "all.f64.json"));
  EXPECT_EQ(side["dtype"], "float64");
  EXPECT_EQ(side["fields"], json({"point", "d1", "d2"}));
  const Curve curve = loadCurve("butterfly_aeb.json");
  const auto spans = curveGridItems(curve);
  const auto bytes = readBytes(dir / "all.f64");
  ASSERT_EQ(bytes.size(), spans.size() * 7 * 9 * 8);
  const double* d = reinterpret_cast<const double*>(bytes.data());
  const double tol = kFp64Rel * extent(curve.model().points) * 100;
  for (size_t k = 0; k < spans.size(); ++k) {
    for (int s = 0; s < 7; ++s) {
      const double* rec = d + (k * 7 + static_cast<size_t>(s)) * 9;
      const CurvePoint cp = curve.evaluate(spans[k], s / 6.0);
      expectNear(cp.point, {rec[0], rec[1], rec[2]}, tol, "point");
      expectNear(cp.d1, {rec[3], rec[4], rec[5]}, tol, "d1");
      expectNear(cp.d2, {rec[6], rec[7], rec[8]}, tol * 10, "d2");
    }
  }
  std::vector<char> joined;
  std::vector<std::string> shardFiles;
  for (int k = 1; k <= 3; ++k) {
    const std::string f = (dir / ("part" + std::to_string(k) + ".f64")).string();
    ASSERT_EQ(runCli("sample " + model + " -o " + quote(f) + " --samples 7 --derivatives --device cpu -q --shard " +
                         std::to_string(k) + "/3",
                     dir.path()).rc, 0);
    const auto b = readBytes(f);
    joined.insert(joined.end(), b.begin(), b.end());
    shardFiles.push_back(quote(f));
    EXPECT_EQ(json::parse(readText(f + ".json"))["shard"]["index"], k);
  }
  EXPECT_EQ(joined, bytes);
  ASSERT_EQ(runCli("merge -o " + quote((dir / "merged.f64").string()) + " " + shardFiles[0] + " " + shardFiles[1] +
                       " " + shardFiles[2],
                   dir.path()).rc, 0);
  EXPECT_EQ(readBytes(dir / "merged.f64"), bytes);
  EXPECT_EQ(json::parse(readText(dir / "merged.f64.json"))["counts"], side["counts"]);
}

TEST(CliSample, Float32RawWithinFp32Tolerance) {
  ScratchDir dir("raw_f32");
  ASSERT_EQ(runCli("sample " + quote(examplesDir() + "/surface_aeb.json") + " -o " + quote((dir / "s.f32").string()) +
                       " --grid 4 --precision float -q",
                   dir.path()).rc, 0);
  const Surface surface = loadSurface("surface_aeb.json");
  const auto items = surfaceGridItems(surface);
  const auto bytes = readBytes(dir / "s.f32");
  ASSERT_EQ(bytes.size(), items.size() * 16 * 3 * 4);
  const float* f = reinterpret_cast<const float*>(bytes.data());
  const double tol = kFp32Rel * extent(surface.controlPoints());
  for (size_t k = 0; k < items.size(); ++k) {
    for (int q = 0; q < 16; ++q) {
      const float* rec = f + (k * 16 + static_cast<size_t>(q)) * 3;
      expectNear(surface.evaluate(items[k].first, items[k].second, (q / 4) / 3.0, (q % 4) / 3.0).point,
                 {rec[0], rec[1], rec[2]}, tol, "point");
    }
  }
}

// Per-item layout (welded shards: tests/cli/mesh_output_test.cpp).
TEST(CliSample, PlyAndObjShardsMergeIntoTheWhole) {
  ScratchDir dir("mesh_shards");
  const std::string model = quote(examplesDir() + "/surface_aeb.json");
  for (const char* ext : {"ply", "obj"}) {
    const std::string whole = (dir / (std::string("all.") + ext)).string();
    ASSERT_EQ(runCli("sample " + model + " -o " + quote(whole) + " --grid 3 --device cpu -q --mesh-layout per-item", dir.path()).rc, 0);
    std::string parts, catted;
    for (int k = 1; k <= 4; ++k) {
      const std::string f = (dir / ("p" + std::to_string(k) + "." + ext)).string();
      ASSERT_EQ(runCli("sample " + model + " -o " + quote(f) + " --grid 3 --device cpu -q --mesh-layout per-item --shard " +
                           std::to_string(k) + "/4",
                       dir.path()).rc, 0);
      parts += " " + quote(f);
      catted += readText(f);
    }
    const std::string merged = (dir / (std::string("merged.") + ext)).string();
    const CliResult m = runCli("merge -o " + quote(merged) + parts, dir.path());
    ASSERT_EQ(m.rc, 0) << m.err;
    if (std::string(ext) == "ply") {
      EXPECT_EQ(readText(merged), readText(whole));
    } else {
      const Obj a = parseObj(readText(whole)), b = parseObj(readText(merged)), c = parseObj(catted);
      EXPECT_EQ(a.v, b.v);
      EXPECT_EQ(a.faces, b.faces);
      EXPECT_EQ(a.v, c.v);
      EXPECT_EQ(a.faces, c.faces);  // relative indices: plain concatenation is the whole mesh
    }
  }
}

TEST(CliSample, VulkanMatchesCpuWithinFp64Tolerance) {
  ScratchDir dir("vulkan_grid");
  const CliResult r = runCli("sample " + quote(examplesDir() + "/surface_aeb.json") + " -o " +
                                 quote((dir / "g.f64").string()) + " --grid 5 --derivatives --normals --device vulkan",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  if (r.err.find("falling back") != std::string::npos) GTEST_SKIP() << "no Vulkan device: " << r.err;
  ASSERT_EQ(runCli("sample " + quote(examplesDir() + "/surface_aeb.json") + " -o " + quote((dir / "c.f64").string()) +
                       " --grid 5 --derivatives --normals --device cpu",
                   dir.path()).rc, 0);
  const auto g = readBytes(dir / "g.f64"), c = readBytes(dir / "c.f64");
  ASSERT_EQ(g.size(), c.size());
  const double* a = reinterpret_cast<const double*>(g.data());
  const double* b = reinterpret_cast<const double*>(c.data());
  for (size_t i = 0; i < g.size() / 8; ++i) ASSERT_NEAR(a[i], b[i], 1e-9) << "value " << i;
}

TEST(CliSample, SvgCurveHasPolygonAndDataPoints) {
  ScratchDir dir("svg");
  ASSERT_EQ(runCli("sample " + quote(examplesDir() + "/butterfly_aeb.json") + " -o " + quote((dir / "b.svg").string()) +
                       " --device cpu -q",
                   dir.path()).rc, 0);
  const std::string svg = readText(dir / "b.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);  // control polygon
  EXPECT_NE(svg.find("<circle"), std::string::npos);           // data points
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

}  // namespace
}  // namespace shapespline::test
