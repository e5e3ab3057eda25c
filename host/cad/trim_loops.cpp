#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/trim_loops.h>
#include <shapespline/core/trim_classifier.h>

#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Wire.hxx>

#include <glm/geometric.hpp>

#include <algorithm>

namespace shapespline::cad {
namespace {

constexpr int kPiecesPerEdge = 8;  // before subdivision: a full circle is never one chord
constexpr int kMaxDepth = 24;

class EdgeFlattener {
 public:
  EdgeFlattener(const TopoDS_Edge& edge, const Handle(Geom2d_Curve)& curve, TrimPoints& points, double tolerance)
      : edge_(edge), curve_(curve), points_(points), tolerance_(tolerance) {}

  // Appends the points after `from` up to and including `to` (the caller holds the first point).
  void append(double from, double to, std::vector<glm::dvec2>& out) const {
    glm::dvec2 a = at(from);
    for (int k = 1; k <= kPiecesPerEdge; ++k) {
      const double t = from + (to - from) * k / kPiecesPerEdge;
      const glm::dvec2 b = at(t);
      subdivide(from + (to - from) * (k - 1) / kPiecesPerEdge, a, t, b, 0, out);
      a = b;
    }
  }
  glm::dvec2 at(double t) const {
    const gp_Pnt2d p = curve_->Value(t);
    return points_(edge_, p.X(), p.Y());
  }

 private:
  void subdivide(double ta, glm::dvec2 a, double tb, glm::dvec2 b, int depth, std::vector<glm::dvec2>& out) const {
    const double tm = 0.5 * (ta + tb);
    const glm::dvec2 m = at(tm);
    const bool flat = distanceToSegment(m, a, b) <= tolerance_ &&
                      distanceToSegment(at(0.5 * (ta + tm)), a, b) <= tolerance_ &&
                      distanceToSegment(at(0.5 * (tm + tb)), a, b) <= tolerance_;
    if (flat || depth >= kMaxDepth) {
      out.push_back(b);
      return;
    }
    subdivide(ta, a, tm, m, depth + 1, out);
    subdivide(tm, m, tb, b, depth + 1, out);
  }

  const TopoDS_Edge& edge_;
  Handle(Geom2d_Curve) curve_;
  TrimPoints& points_;
  double tolerance_;
};

std::vector<glm::dvec2> wireLoop(const TopoDS_Wire& wire, const TopoDS_Face& face, TrimPoints& points,
                                 double tolerance) {
  std::vector<glm::dvec2> loop;
  for (BRepTools_WireExplorer edges(wire, face); edges.More(); edges.Next()) {
    const TopoDS_Edge& edge = edges.Current();
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) curve = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (curve.IsNull()) throw ConversionError("an edge of the face has no curve on its surface (p-curve)");
    const bool reversed = edge.Orientation() == TopAbs_REVERSED;
    const EdgeFlattener flattener(edge, curve, points, tolerance);
    if (loop.empty()) loop.push_back(flattener.at(reversed ? last : first));
    flattener.append(reversed ? last : first, reversed ? first : last, loop);
  }
  // Consecutive edges meet within their tolerance: the last point closes the loop.
  if (loop.size() > 1 && glm::length(loop.back() - loop.front()) <= tolerance) loop.pop_back();
  return loop;
}

}  // namespace

double signedArea(const std::vector<glm::dvec2>& loop) {
  double twice = 0.0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const glm::dvec2 a = loop[i], b = loop[(i + 1) % loop.size()];
    twice += a.x * b.y - b.x * a.y;
  }
  return 0.5 * twice;
}

TrimLoops faceTrimLoops(const TopoDS_Face& face, TrimPoints& points, double tolerance) {
  const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  const TopoDS_Wire outer = BRepTools::OuterWire(forward);
  TrimLoops trim;
  trim.tolerance = tolerance;
  std::vector<std::vector<glm::dvec2>> holes;
  for (TopExp_Explorer wires(forward, TopAbs_WIRE); wires.More(); wires.Next()) {
    const TopoDS_Wire& wire = TopoDS::Wire(wires.Current());
    std::vector<glm::dvec2> loop = wireLoop(wire, forward, points, tolerance);
    if (loop.size() < 3) throw ConversionError("a wire of the face gives fewer than 3 trim points");
    const bool isOuter = wire.IsSame(outer);
    if ((signedArea(loop) > 0.0) != isOuter) std::reverse(loop.begin(), loop.end());
    (isOuter ? trim.loops : holes).push_back(std::move(loop));
  }
  if (trim.loops.size() != 1) throw ConversionError("the face has no outer wire");
  for (auto& hole : holes) trim.loops.push_back(std::move(hole));
  return trim;
}

}  // namespace shapespline::cad
