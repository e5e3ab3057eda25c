// io/welded_mesh.h: the numbering is a bijection onto the distinct grid points in emission order,
// the meshes are closed/bounded as their grids, shards reproduce the whole job's vertices, and the
// stream averages normals in item order.
#include <shapespline/io/welded_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <tuple>

namespace shapespline::io {
namespace {

struct GridCase {
  uint64_t pu, pv;
  int su, sv;
  bool cu, cv;
};

std::vector<GridCase> cases() {
  std::vector<GridCase> out = {
      {1, 1, 2, 2, false, false}, {1, 1, 3, 4, true, true},  {1, 1, 2, 2, true, true},  {3, 2, 4, 3, true, false},
      {2, 3, 3, 5, false, true},  {4, 4, 3, 3, true, true},   {2, 1, 5, 1, false, false}, {3, 1, 4, 1, true, false},
      {1, 1, 6, 1, true, false},  {5, 3, 2, 2, false, false}, {2, 2, 2, 3, true, true},
  };
  return out;
}

// The point of (item, a, b) computed independently: global row/column, wrapped.
std::pair<uint64_t, uint64_t> expectedPoint(const GridCase& g, uint64_t item, int a, int b) {
  const uint64_t rows = g.pu * (g.su - 1) + (g.cu ? 0 : 1);
  const uint64_t cols = g.sv == 1 ? 1 : g.pv * (g.sv - 1) + (g.cv ? 0 : 1);
  const uint64_t r = item / g.pv, c = item % g.pv;
  return {(r * (g.su - 1) + a) % rows, g.sv == 1 ? 0 : (c * (g.sv - 1) + b) % cols};
}

TEST(WeldGrid, EmittingSamplesNumberTheDistinctPointsInOrder) {
  for (const GridCase& g : cases()) {
    SCOPED_TRACE(::testing::Message() << g.pu << "x" << g.pv << " items of " << g.su << "x" << g.sv << " closed "
                                      << g.cu << g.cv);
    const WeldGrid grid(g.pu, g.pv, g.su, g.sv, g.cu, g.cv);
    std::set<std::pair<uint64_t, uint64_t>> distinct;
    std::map<std::pair<uint64_t, uint64_t>, int> samples;
    uint64_t next = 0;
    for (uint64_t item = 0; item < grid.items(); ++item) {
      EXPECT_EQ(grid.firstIndexOf(item), next);
      for (int a = 0; a < g.su; ++a) {
        for (int b = 0; b < g.sv; ++b) {
          const auto e = expectedPoint(g, item, a, b);
          const WeldGrid::Point p = grid.pointOf(item, a, b);
          ASSERT_EQ(std::make_pair(p.row, p.column), e);
          distinct.insert(e);
          ++samples[e];
          if (grid.emits(item, a, b)) {
            EXPECT_EQ(grid.globalIndex(p), next) << "emission order";
            EXPECT_EQ(grid.ownerOf(p), item);
            ++next;
          }
        }
      }
    }
    EXPECT_EQ(next, distinct.size());
    EXPECT_EQ(grid.pointCount(), distinct.size());
    EXPECT_EQ(grid.firstIndexOf(grid.items()), grid.pointCount());
    for (const auto& [e, n] : samples) {
      const WeldGrid::Point p{e.first, e.second};
      EXPECT_EQ(grid.sampleCount(p), n);
      // The owner is the last item containing the point.
      std::vector<uint64_t> items = grid.itemsContaining(p);
      ASSERT_FALSE(items.empty());
      EXPECT_EQ(grid.ownerOf(p), items.back());
    }
  }
}

// Edges of a triangle list -> number of triangles using each.
std::map<std::pair<uint64_t, uint64_t>, int> edgeUse(const WeldedNumbering& n) {
  std::map<std::pair<uint64_t, uint64_t>, int> use;
  n.forEachTriangle(false, [&](uint64_t i, uint64_t j, uint64_t k) {
    for (auto [x, y] : {std::pair{i, j}, std::pair{j, k}, std::pair{k, i}}) ++use[{std::min(x, y), std::max(x, y)}];
  });
  return use;
}

TEST(WeldedNumbering, MeshesAreClosedExactlyWhereTheirGridsAre) {
  for (const GridCase& g : cases()) {
    if (g.sv == 1 || (g.su < 3 && g.cu) || (g.sv < 3 && g.cv)) continue;  // a 2-sample closed direction folds onto itself
    if ((g.cu && g.pu * (g.su - 1) < 3) || (g.cv && g.pv * (g.sv - 1) < 3)) continue;
    SCOPED_TRACE(::testing::Message() << g.pu << "x" << g.pv << " closed " << g.cu << g.cv);
    const WeldGrid grid(g.pu, g.pv, g.su, g.sv, g.cu, g.cv);
    const WeldedNumbering whole(grid, 0, grid.items());
    const auto use = edgeUse(whole);
    int boundary = 0;
    for (const auto& [e, n] : use) {
      EXPECT_LE(n, 2);
      if (n == 1) ++boundary;
    }
    const long long rows = static_cast<long long>(grid.rows()), cols = static_cast<long long>(grid.columns());
    const long long expectBoundary = (g.cu ? 0 : 2 * (g.cv ? cols : cols - 1)) + (g.cv ? 0 : 2 * (g.cu ? rows : rows - 1));
    EXPECT_EQ(boundary, expectBoundary);
    const long long v = static_cast<long long>(whole.vertexCount()), e = static_cast<long long>(use.size()),
                    f = static_cast<long long>(whole.triangleCount());
    // Torus 0, cylinder 0, disc 1.
    EXPECT_EQ(v - e + f, g.cu && g.cv ? 0 : g.cu || g.cv ? 0 : 1);
  }
}

TEST(WeldedNumbering, ShardsNumberTheirPointsOwnedFirstThenForeign) {
  std::mt19937 rng(7);
  for (const GridCase& g : cases()) {
    const WeldGrid grid(g.pu, g.pv, g.su, g.sv, g.cu, g.cv);
    for (int trial = 0; trial < 6; ++trial) {
      const uint64_t f = rng() % grid.items(), e = f + 1 + rng() % (grid.items() - f);
      SCOPED_TRACE(::testing::Message() << g.pu << "x" << g.pv << " closed " << g.cu << g.cv << " items " << f << ".." << e);
      const WeldedNumbering shard(grid, f, e);
      std::set<uint64_t> locals;
      std::set<std::pair<uint64_t, uint64_t>> points;
      for (uint64_t item = f; item < e; ++item) {
        for (int a = 0; a < g.su; ++a) {
          for (int b = 0; b < g.sv; ++b) {
            const WeldGrid::Point p = grid.pointOf(item, a, b);
            points.insert({p.row, p.column});
            const uint64_t local = shard.localIndex(p);
            locals.insert(local);
            if (grid.ownerOf(p) < e) {
              EXPECT_EQ(local, grid.globalIndex(p) - grid.firstIndexOf(f));
            } else {
              EXPECT_GE(local, shard.ownedCount());
            }
          }
        }
      }
      EXPECT_EQ(locals.size(), points.size());
      EXPECT_EQ(shard.vertexCount(), points.size());
      EXPECT_EQ(*locals.rbegin() + 1, shard.vertexCount());
      // Context: exactly the outside items sharing a point.
      std::set<uint64_t> expectContext;
      for (const auto& [row, col] : points) {
        for (uint64_t item : grid.itemsContaining({row, col})) {
          if (item < f || item >= e) expectContext.insert(item);
        }
      }
      std::set<uint64_t> context;
      for (const auto& [x, y] : shard.contextItems()) {
        for (uint64_t k = x; k < y; ++k) context.insert(k);
      }
      EXPECT_EQ(context, expectContext);
    }
  }
}

TEST(WeldedNumbering, ClosedCurvePolylineIsOneLoop) {
  const WeldGrid grid(3, 1, 4, 1, true, false);
  const WeldedNumbering whole(grid, 0, 3);
  std::vector<uint64_t> path;
  whole.forEachPolylinePoint([&](uint64_t i) { path.push_back(i); });
  ASSERT_EQ(path.size(), whole.polylineLength());
  EXPECT_EQ(path.size(), grid.pointCount() + 1);
  EXPECT_EQ(path.front(), path.back());
  std::set<uint64_t> distinct(path.begin(), path.end());
  EXPECT_EQ(distinct.size(), grid.pointCount());
  const WeldGrid open(3, 1, 4, 1, false, false);
  const WeldedNumbering line(open, 0, 3);
  std::vector<uint64_t> openPath;
  line.forEachPolylinePoint([&](uint64_t i) { openPath.push_back(i); });
  for (size_t k = 0; k < openPath.size(); ++k) EXPECT_EQ(openPath[k], k);  // in order, no repeated joint
}

// Chunks whose point value is the sample's item (so the canonical sample shows) and whose normal
// depends on the item, streamed whole and as shards with their context.
struct Synthetic {
  GridCase g;
  std::vector<double> point, normal;
  GridChunk chunk(uint64_t item) {
    const size_t ppi = static_cast<size_t>(g.su) * static_cast<size_t>(g.sv);
    point.assign(ppi * 3, 0.0);
    normal.assign(ppi * 3, 0.0);
    for (size_t q = 0; q < ppi; ++q) {
      point[q * 3] = static_cast<double>(item);
      point[q * 3 + 1] = static_cast<double>(q);
      const double t = 0.1 * static_cast<double>(item);
      normal[q * 3] = std::cos(t);
      normal[q * 3 + 1] = std::sin(t);
    }
    GridChunk c;
    c.firstItem = item;
    c.itemCount = 1;
    c.pointsPerItem = ppi;
    c.pointsPerRow = static_cast<size_t>(g.sv);
    c.planes[static_cast<size_t>(Field::Point)] = point.data();
    c.planes[static_cast<size_t>(Field::Normal)] = normal.data();
    return c;
  }
};

using Vertex = std::tuple<double, double, double, double, double, uint64_t, int, int>;

std::vector<Vertex> stream(const GridCase& g, uint64_t f, uint64_t e, bool withContext) {
  const WeldGrid grid(g.pu, g.pv, g.su, g.sv, g.cu, g.cv);
  const WeldedNumbering numbering(grid, f, e);
  std::vector<Vertex> out;
  WeldedVertexStream s(numbering, fieldBit(Field::Point) | fieldBit(Field::Normal), false, [&](const WeldedVertex& v) {
    out.emplace_back(v.value(Field::Point, 0), v.value(Field::Point, 1), v.value(Field::Normal, 0),
                     v.value(Field::Normal, 1), v.value(Field::Normal, 2), v.item, v.a, v.b);
  });
  std::vector<uint64_t> items;
  for (uint64_t k = f; k < e; ++k) items.push_back(k);
  if (withContext) {
    for (const auto& [x, y] : numbering.contextItems()) {
      for (uint64_t k = x; k < y; ++k) items.push_back(k);
    }
  }
  std::sort(items.begin(), items.end());
  Synthetic syn{g, {}, {}};
  for (uint64_t k : items) s.consume(syn.chunk(k));
  s.finish();
  EXPECT_EQ(out.size(), numbering.vertexCount());
  return out;
}

TEST(WeldedVertexStream, ShardsReproduceTheWholeJobsVertices) {
  for (const GridCase& g : cases()) {
    const WeldGrid grid(g.pu, g.pv, g.su, g.sv, g.cu, g.cv);
    SCOPED_TRACE(::testing::Message() << g.pu << "x" << g.pv << " closed " << g.cu << g.cv);
    const std::vector<Vertex> whole = stream(g, 0, grid.items(), false);
    // Canonical sample = lowest item containing the point; normal = normalised mean over samples.
    for (uint64_t gi = 0; gi < whole.size(); ++gi) {
      const auto& v = whole[gi];
      const WeldGrid::Point p = grid.pointOf(std::get<5>(v), std::get<6>(v), std::get<7>(v));
      EXPECT_EQ(grid.globalIndex(p), gi);
      EXPECT_EQ(std::get<5>(v), grid.itemsContaining(p).front());
      EXPECT_EQ(std::get<0>(v), static_cast<double>(std::get<5>(v)));
      EXPECT_NEAR(std::hypot(std::get<2>(v), std::get<3>(v)), 1.0, 1e-15);
    }
    for (uint64_t f = 0; f < grid.items(); ++f) {
      for (uint64_t e = f + 1; e <= grid.items(); ++e) {
        const std::vector<Vertex> shard = stream(g, f, e, true);
        const uint64_t base = grid.firstIndexOf(f), owned = grid.firstIndexOf(e) - base;
        for (uint64_t k = 0; k < owned; ++k) ASSERT_EQ(shard[k], whole[base + k]) << "shard " << f << ".." << e;
        // Foreign points equal the whole job's too (the context supplied every sample).
        const WeldedNumbering numbering(grid, f, e);
        for (size_t k = 0; k < numbering.foreignPoints().size(); ++k) {
          ASSERT_EQ(shard[owned + k], whole[numbering.foreignPoints()[k]]);
        }
      }
    }
  }
}

TEST(WeldedVertexStream, MissingContextIsAnError) {
  const GridCase g{3, 1, 3, 3, false, false};
  EXPECT_THROW(stream(g, 0, 1, false), std::logic_error);
}

}  // namespace
}  // namespace shapespline::io
