#include <shapespline/part/projection_tables.h>

#include <shapespline/core/trim_classifier.h>
#include <shapespline/part/closest_points.h>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <tuple>

namespace shapespline::part {

namespace pl = gpu::projection_layout;

namespace {

// fp32 stops Newton at a step of this many local units (about 8 ulps of 1; fp32 settles within a
// few ulps and no nearer) and takes a foot within this fraction of the diagonal as on the surface
// (the distance's own rounding, a few ulps of the part's size). fp64 uses ClosestPoints' own.
constexpr double kFloatStepTolerance = 1e-6;
constexpr double kFloatOnSurfaceFraction = 1e-6;
constexpr int kLeastPaddedDegree = 3;

void put3(std::vector<double>& out, const glm::dvec3& v) { out.insert(out.end(), {v.x, v.y, v.z}); }

void putBox(std::vector<double>& out, const Box& box, const glm::dvec3& origin) {
  put3(out, box.lo - origin);
  put3(out, box.hi - origin);
}

uint32_t index(size_t k) { return static_cast<uint32_t>(k); }

}  // namespace

FlatProjectionTree flattenProjectionTree(const ProjectionTree& tree, double tolerance, Precision precision) {
  if (tree.curve()) throw std::invalid_argument("flattenProjectionTree: the GPU search takes surfaces and parts");
  FlatProjectionTree flat;
  gpu::ProjectionTables& t = flat.tables;
  std::vector<double>& reals = t.reals;
  std::vector<uint32_t>& ints = t.ints;
  pl::ProjectionPush& at = t.offsets;
  if (!tree.nodes().empty()) flat.origin = tree.nodes().front().box.centre();
  const glm::dvec3 origin = flat.origin;
  const bool fp64 = precision == Precision::Double;
  const double onSurface = (fp64 ? ClosestPoints::kOnSurfaceFraction : kFloatOnSurfaceFraction) * tree.diagonal();
  reals = {tolerance, tree.diagonal(), fp64 ? ClosestPoints::kStepTolerance : kFloatStepTolerance, onSurface * onSurface,
           ClosestPoints::kTrustedStep};

  at.nodeReals = index(reals.size());
  at.nodeInts = index(ints.size());
  for (const ProjectionTree::Node& node : tree.nodes()) {
    putBox(reals, node.box, origin);
    ints.insert(ints.end(), {index(node.first), index(node.count), index(node.right), 0u});
  }
  at.leafReals = index(reals.size());
  at.leafInts = index(ints.size());
  for (const ProjectionTree::Leaf& leaf : tree.leaves()) {
    putBox(reals, leaf.box, origin);
    ints.push_back(index(leaf.index));
  }

  // Faces: each one's low corner, and where its patch (i, j) sits among its non-empty intervals.
  const std::vector<ProjectionFace>& faces = tree.faces();
  for (const ProjectionFace& face : faces)
    flat.faceCorners.push_back({face.surface->parameterRangeU().first, face.surface->parameterRangeV().first});

  at.runListInts = index(ints.size());
  std::vector<uint32_t> runStart(tree.cells().size() + 1);
  for (size_t c = 0; c < tree.cells().size(); ++c) {
    runStart[c] = index(ints.size() - at.runListInts);
    for (const int r : tree.runsOf(static_cast<int>(c))) ints.push_back(index(r));
  }
  runStart.back() = index(ints.size() - at.runListInts);

  at.cellReals = index(reals.size());
  at.cellInts = index(ints.size());
  for (const ProjectionCell& cell : tree.cells()) {
    const Surface& s = *faces[cell.face].surface;
    const glm::dvec2 corner = flat.faceCorners[cell.face];
    const auto [U0, V0] = s.parameterOf(cell.i, cell.j, 0.0, 0.0);
    const auto [U1, V1] = s.parameterOf(cell.i, cell.j, 1.0, 1.0);
    reals.insert(reals.end(), {cell.u0, cell.u1, cell.v0, cell.v1, U0 - corner.x, U1 - U0, V0 - corner.y, V1 - V0});
    put3(reals, cell.middle - origin);
    put3(reals, cell.alongU);
    put3(reals, cell.alongV);
    reals.insert(reals.end(), {cell.bendsUp, cell.bendsDown});
    for (const glm::dvec3& axis : cell.axis) put3(reals, axis);
    reals.insert(reals.end(), {cell.lo[0], cell.lo[1], cell.lo[2], cell.hi[0], cell.hi[1], cell.hi[2]});
    // The sides on the domain's border (not a closed direction's seam), as solveCell tests them.
    const auto [uMin, uMax] = s.parameterRangeU();
    const auto [vMin, vMax] = s.parameterRangeV();
    const SurfaceShape& shape = s.model();
    uint32_t borders = 0;
    for (int side = 0; side < 4; ++side) {
      const bool alongV = side < 2;
      const double fixed = side == 0 ? cell.u0 : side == 1 ? cell.u1 : side == 2 ? cell.v0 : cell.v1;
      const auto [U, V] = alongV ? s.parameterOf(cell.i, cell.j, fixed, cell.v0) : s.parameterOf(cell.i, cell.j, cell.u0, fixed);
      const bool border = alongV ? !shape.closedU && (U == uMin || U == uMax) : !shape.closedV && (V == vMin || V == vMax);
      if (border) borders |= 1u << side;
    }
    const size_t c = static_cast<size_t>(cell.index);
    ints.insert(ints.end(), {index(cell.face), index(cell.patch), index(cell.i), index(cell.j), runStart[c],
                             runStart[c + 1], borders, 0u});
  }

  // Patches, padded with zeros to the largest degrees (the kernel's Horner loops have constant
  // counts), their power forms moved to the origin: (w P, w) -> (w (P - o), w), term by term. At
  // least bicubic: one compiled kernel serves every part of degree 3 or less (lavapipe takes tens of
  // seconds to compile one), for a few more terms on planes and quadrics.
  t.degreeU = t.degreeV = kLeastPaddedDegree;
  for (const ProjectionPatch& patch : tree.patches()) {
    t.degreeU = std::max(t.degreeU, patch.n);
    t.degreeV = std::max(t.degreeV, patch.m);
  }
  const size_t padded = static_cast<size_t>(t.degreeU + 1) * (t.degreeV + 1);
  t.coefficients.assign(padded * tree.patches().size(), glm::dvec4(0.0));
  at.patchInts = index(ints.size());
  for (size_t p = 0; p < tree.patches().size(); ++p) {
    const ProjectionPatch& patch = tree.patches()[p];
    ints.insert(ints.end(), {index(patch.n), index(patch.m), index(p * padded), patch.rational ? 1u : 0u});
    for (int d = 0; d <= patch.n; ++d)
      for (int e = 0; e <= patch.m; ++e) {
        const glm::dvec4& c = tree.coefficients()[patch.first + static_cast<size_t>(d) * (patch.m + 1) + e];
        t.coefficients[p * padded + static_cast<size_t>(d) * (t.degreeV + 1) + e] = glm::dvec4(glm::dvec3(c) - origin * c.w, c.w);
      }
  }

  at.runReals = index(reals.size());
  at.runInts = index(ints.size());
  for (const ProjectionRun& run : tree.runs()) {
    const std::vector<glm::dvec2>& loop = faces[run.face].surface->model().trim.loops[run.loop];
    const glm::dvec2 a = loop[run.segment], b = loop[(run.segment + 1) % loop.size()];
    const glm::dvec2 corner = flat.faceCorners[run.face];
    reals.insert(reals.end(), {a.x - corner.x, a.y - corner.y, b.x - a.x, b.y - a.y, run.t0, run.t1});
    putBox(reals, run.box, origin);
    ints.push_back(index(run.face));
  }

  // Per face: the trim classifier's edges and slabs, the patch boundaries and the patch table.
  std::map<std::tuple<int, int, int>, int> patchOf;
  for (size_t p = 0; p < tree.patches().size(); ++p) {
    const ProjectionPatch& patch = tree.patches()[p];
    patchOf[{patch.face, patch.i, patch.j}] = static_cast<int>(p);
  }
  std::vector<double> edges;
  std::vector<uint32_t> faceInts;
  std::vector<double> faceReals;
  for (size_t f = 0; f < faces.size(); ++f) {
    const Surface& s = *faces[f].surface;
    const glm::dvec2 corner = flat.faceCorners[f];
    const auto [uMin, uMax] = s.parameterRangeU();
    const auto [vMin, vMax] = s.parameterRangeV();
    uint32_t edgeFirst = index(edges.size() / 4), edgeCount = 0, slabs = 0, slabStart = 0, slabEdges = 0;
    double v0 = 0.0, height = 1.0, tol = 0.0;
    if (!s.model().trim.empty()) {
      const TrimClassifier classifier(s.model().trim);
      for (const TrimClassifier::Edge& e : classifier.edges())
        edges.insert(edges.end(), {e.a.x - corner.x, e.a.y - corner.y, e.b.x - corner.x, e.b.y - corner.y});
      edgeCount = index(classifier.edges().size());
      slabs = index(classifier.slabs());
      slabStart = index(ints.size());
      for (const int k : classifier.slabStart()) ints.push_back(index(k));
      slabEdges = index(ints.size());
      for (const int k : classifier.slabEdges()) ints.push_back(index(k));
      v0 = classifier.v0() - corner.y, height = classifier.slabHeight(), tol = classifier.tolerance();
    }
    // The non-empty intervals' boundaries along U, then V, and the tree patch of each pair.
    const PatchRange range = s.patches();
    std::vector<int> is, js;
    for (int i = range.u.first; i <= range.u.last; ++i)
      if (s.parameterOf(i, range.v.first, 0.0, 0.0).first != s.parameterOf(i, range.v.first, 1.0, 0.0).first) is.push_back(i);
    for (int j = range.v.first; j <= range.v.last; ++j)
      if (s.parameterOf(range.u.first, j, 0.0, 0.0).second != s.parameterOf(range.u.first, j, 0.0, 1.0).second) js.push_back(j);
    const uint32_t breaks = index(reals.size());
    for (const int i : is) reals.push_back(s.parameterOf(i, range.v.first, 0.0, 0.0).first - corner.x);
    reals.push_back(uMax - corner.x);
    for (const int j : js) reals.push_back(s.parameterOf(range.u.first, j, 0.0, 0.0).second - corner.y);
    reals.push_back(vMax - corner.y);
    const uint32_t table = index(ints.size());
    for (const int i : is)
      for (const int j : js) ints.push_back(index(patchOf.at({static_cast<int>(f), i, j})));
    faceInts.insert(faceInts.end(), {edgeFirst, edgeCount, slabs, slabStart, slabEdges, breaks, index(is.size()), table,
                                     static_cast<uint32_t>(faces[f].id), index(js.size())});
    faceReals.insert(faceReals.end(), {uMax - uMin, vMax - vMin, v0, height, tol});
  }
  at.faceReals = index(reals.size());
  reals.insert(reals.end(), faceReals.begin(), faceReals.end());
  at.faceInts = index(ints.size());
  ints.insert(ints.end(), faceInts.begin(), faceInts.end());
  at.edgeReals = index(reals.size());
  reals.insert(reals.end(), edges.begin(), edges.end());
  return flat;
}

}  // namespace shapespline::part
