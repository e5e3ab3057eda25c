#include <shapespline/core/model.h>
#include <shapespline/core/parallel_for.h>
#include <shapespline/core/value_text.h>
#include <shapespline/part/edge_discretisation.h>
#include <shapespline/part/face_triangulation.h>
#include <shapespline/part/loop_projection.h>
#include <shapespline/part/part_mesher.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace shapespline::part {
namespace {

// The edges and faces are cut to this fraction of the deflection asked for. Their tests look at a
// chord's middle and quarter points and a triangle's centroid and edge midpoints, and the surface
// can bulge a little further between them: at 0.9 the largest distance measured by projection
// (bench/cad/part_mesh.cpp) reached 1.07 D on a free-form IGES part; at 0.85 it is 0.86 D at most.
constexpr double kDeflectionMargin = 0.85;

// Vertex ids merged where consecutive coedges of a loop meet (a CAD vertex): union-find.
class VertexSets {
 public:
  explicit VertexSets(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), uint32_t{0}); }
  uint32_t find(uint32_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // the lowest id represents: deterministic
  }

 private:
  std::vector<uint32_t> parent_;
};

CoedgePaths coedgePaths(const Part& part) {
  CoedgePaths paths(part.faces.size());
  for (size_t f = 0; f < part.faces.size(); ++f) {
    const PartFace& face = part.faces[f];
    const auto& loops = face.surface.model().trim.loops;
    if (face.coedges.empty())
      throw ModelError(face.field + ".coedges", "", "part.json gives no coedges for the face (it was imported before "
                                                   "meshing existed): import the part again");
    for (size_t l = 0; l < loops.size(); ++l) {
      auto& loopPaths = paths[f].emplace_back();
      for (size_t c = 0; c < face.coedges[l].size(); ++c) {
        const io::PartCoedge& coedge = face.coedges[l][c];
        if (static_cast<size_t>(coedge.start) >= loops[l].size() || coedge.t.size() > loops[l].size() + 1)
          throw ModelError(face.field + ".coedges[" + std::to_string(l) + "][" + std::to_string(c) + "]",
                           "start " + std::to_string(coedge.start) + ", " + std::to_string(coedge.t.size()) + " points",
                           "must lie on the face's trim loop " + std::to_string(l) + " of " +
                               std::to_string(loops[l].size()) + " points");
        loopPaths.emplace_back(coedge, loops[l]);
      }
    }
  }
  return paths;
}

}  // namespace

double partDiagonal(const Part& part) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const PartFace& face : part.faces)
    face.surface.forEachControlPoint([&](const glm::dvec3& p) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    });
  return part.faces.empty() ? 0.0 : glm::length(hi - lo);
}

PartMesh meshPart(const Part& part, const MeshOptions& options, FaceEvaluator& evaluator) {
  const auto overBudget = [&](const std::string& where) {
    return TriangleBudgetExceeded("the mesh at deflection " + shortestText(options.deflection) +
                                  " needs more than the budget of " + std::to_string(options.maxTriangles) +
                                  " triangles (" + where + " reached it)");
  };
  const CoedgePaths paths = coedgePaths(part);
  std::vector<DiscreteEdge> edges;
  try {
    edges = discretiseEdges(part, paths, {kDeflectionMargin * options.deflection, options.angle}, evaluator, options.threads,
                            options.maxTriangles);
  } catch (const TriangleBudgetExceeded&) {
    throw overBudget("the edges");
  }

  // Part-wide vertex ids: edge e's vertex k is base[e] + k.
  std::unordered_map<int, size_t> edgeIndex;
  std::vector<uint32_t> base(edges.size());
  std::vector<glm::dvec3> positions;
  for (size_t e = 0; e < edges.size(); ++e) {
    edgeIndex[edges[e].id] = e;
    base[e] = static_cast<uint32_t>(positions.size());
    positions.insert(positions.end(), edges[e].points.begin(), edges[e].points.end());
  }
  // The edge's vertices in the order a coedge runs along it.
  const auto coedgeVertices = [&](const CoedgePath& path) {
    const size_t e = edgeIndex.at(path.edge());
    std::vector<uint32_t> ids(edges[e].points.size());
    std::iota(ids.begin(), ids.end(), base[e]);
    if (path.descending()) std::reverse(ids.begin(), ids.end());
    return ids;
  };
  VertexSets sets(positions.size());
  for (const auto& face : paths)
    for (const auto& loop : face)
      for (size_t c = 0; c < loop.size(); ++c)
        sets.join(coedgeVertices(loop[c]).back(), coedgeVertices(loop[(c + 1) % loop.size()]).front());
  // Where the face's surface collapses along an edge the file does not call degenerate (a side
  // drawn to a point), the edge's consecutive vertices meet: they are one vertex, as at a pole.
  const double coincident = 1e-9 * partDiagonal(part);
  for (size_t e = 0; e < edges.size(); ++e)
    for (size_t k = 0; k + 1 < edges[e].points.size(); ++k)
      if (glm::length(edges[e].points[k] - edges[e].points[k + 1]) <= coincident)
        sets.join(base[e] + static_cast<uint32_t>(k), base[e] + static_cast<uint32_t>(k + 1));

  // Each face's loops as part-wide vertices, then its triangles.
  std::vector<FaceTriangles> faces(part.faces.size());
  std::vector<std::vector<std::vector<LoopVertex>>> faceLoops(part.faces.size());
  for (size_t f = 0; f < part.faces.size(); ++f)
    for (const auto& loop : paths[f]) {
      auto& vertices = faceLoops[f].emplace_back();
      for (const CoedgePath& path : loop) {
        const DiscreteEdge& edge = edges[edgeIndex.at(path.edge())];
        if (edge.degenerate) {  // a pole: the face's own points along it, all the one vertex
          const uint32_t id = sets.find(base[edgeIndex.at(path.edge())]);
          for (size_t j = 0; j + 1 < path.uv().size(); ++j) vertices.push_back({path.uv()[j], id});
          continue;
        }
        const std::vector<uint32_t> ids = coedgeVertices(path);
        for (size_t k = 0; k + 1 < ids.size(); ++k)
          vertices.push_back({path.uvAt(edge.t[ids[k] - base[edgeIndex.at(path.edge())]]), sets.find(ids[k])});
      }
    }
  std::atomic<int64_t> budget{options.maxTriangles};
  parallelFor(part.faces.size(), options.threads, [&](size_t f) {
    const PartFace& face = part.faces[f];
    projectLoopVertices(face.surface, faceLoops[f], positions, evaluator);
    try {
      faces[f] = triangulateFace(face.surface, face.reversed, faceLoops[f], positions,
                                 {kDeflectionMargin * options.deflection, options.angle}, evaluator, budget);
    } catch (const CrossingTrimLoops& e) {
      throw ModelError(face.field + ".model", face.model.filename().string(),
                       std::string("its trim loops cross each other (") + e.what() + ")");
    } catch (const TriangleBudgetExceeded&) {
      throw overBudget(face.field);
    }
  });

  // Weld: the loop vertices every face shares numbered as first used, each face's interior after.
  PartMesh result;
  io::TriangleMesh& mesh = result.mesh;
  std::vector<uint32_t> index(positions.size(), UINT32_MAX);
  std::vector<glm::dvec3> normalSums;
  const auto shared = [&](uint32_t id) {
    if (index[id] == UINT32_MAX) {
      index[id] = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(positions[id]);
      normalSums.emplace_back(0.0);
    }
    return index[id];
  };
  for (size_t f = 0; f < faces.size(); ++f) {
    const FaceTriangles& face = faces[f];
    const uint32_t interiorBase = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), face.points.begin(), face.points.end());
    normalSums.insert(normalSums.end(), face.normals.begin(), face.normals.end());
    size_t k = 0;
    std::unordered_map<uint32_t, glm::dvec3> loopNormal;  // this face's own, by part-wide vertex id
    for (const auto& loop : faceLoops[f])
      for (const LoopVertex& v : loop) {
        normalSums[shared(v.vertex)] += face.loopNormals[k];
        if (options.cornerNormals) loopNormal.emplace(v.vertex, face.loopNormals[k]);
        ++k;
      }
    for (const auto& t : face.triangles) {
      std::array<uint32_t, 3> out{};
      for (int j = 0; j < 3; ++j)
        out[size_t(j)] = t[size_t(j)] >= FaceTriangles::kInterior ? interiorBase + (t[size_t(j)] - FaceTriangles::kInterior)
                                                                    : shared(t[size_t(j)]);
      if (out[0] == out[1] || out[1] == out[2] || out[0] == out[2]) continue;  // collapsed at a pole
      mesh.triangles.push_back(out);
      mesh.faceIds.push_back(part.faces[f].id);
      if (options.cornerNormals)
        for (uint32_t v : t)  // zero where the face has none: the vertex's mean, filled in below
          result.cornerNormals.emplace_back(v >= FaceTriangles::kInterior ? face.normals[v - FaceTriangles::kInterior]
                                                                          : loopNormal.at(v));
    }
  }
  // Normals: the faces' mean at shared vertices; where the surfaces give none (a pole), the
  // triangles' area-weighted mean.
  std::vector<glm::dvec3> areaSums(mesh.positions.size(), glm::dvec3(0.0));
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 n = glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
    for (uint32_t v : t) areaSums[v] += n;
  }
  mesh.normals.resize(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    glm::dvec3 n = normalSums[v];
    if (!(glm::length(n) > 1e-12)) n = areaSums[v];
    const double l = glm::length(n);
    mesh.normals[v] = l > 0.0 && std::isfinite(l) ? n / l : glm::dvec3(0.0, 0.0, 1.0);
  }
  for (size_t c = 0; c < result.cornerNormals.size(); ++c) {
    const glm::vec3 n = result.cornerNormals[c];
    const float l = glm::length(n);
    result.cornerNormals[c] = l > 1e-6f && std::isfinite(l) ? n / l : glm::vec3(mesh.normals[mesh.triangles[c / 3][c % 3]]);
  }
  // Edges used by one triangle (open) or more than two (non-manifold).
  std::unordered_map<uint64_t, int> uses;
  uses.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles)
    for (int j = 0; j < 3; ++j) {
      const uint32_t a = std::min(t[size_t(j)], t[size_t((j + 1) % 3)]), b = std::max(t[size_t(j)], t[size_t((j + 1) % 3)]);
      ++uses[(uint64_t(a) << 32) | b];
    }
  for (const auto& [key, n] : uses) {
    result.boundaryEdges += n == 1;
    result.nonManifoldEdges += n > 2;
  }
  result.faces = static_cast<int>(part.faces.size());
  result.edges = static_cast<int>(edges.size());
  return result;
}

}  // namespace shapespline::part
