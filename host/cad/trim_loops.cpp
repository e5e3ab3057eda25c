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

  // Appends the points after `from` up to and including `to` (the caller holds the first point), and
  // the edge parameter of each to `ts`.
  void append(double from, double to, std::vector<glm::dvec2>& out, std::vector<double>& ts) const {
    glm::dvec2 a = at(from);
    for (int k = 1; k <= kPiecesPerEdge; ++k) {
      const double t = from + (to - from) * k / kPiecesPerEdge;
      const glm::dvec2 b = at(t);
      subdivide(from + (to - from) * (k - 1) / kPiecesPerEdge, a, t, b, 0, out, ts);
      a = b;
    }
  }
  glm::dvec2 at(double t) const {
    const gp_Pnt2d p = curve_->Value(t);
    return points_(edge_, p.X(), p.Y());
  }

 private:
  void subdivide(double ta, glm::dvec2 a, double tb, glm::dvec2 b, int depth, std::vector<glm::dvec2>& out,
                 std::vector<double>& ts) const {
    const double tm = 0.5 * (ta + tb);
    const glm::dvec2 m = at(tm);
    const bool flat = distanceToSegment(m, a, b) <= tolerance_ &&
                      distanceToSegment(at(0.5 * (ta + tm)), a, b) <= tolerance_ &&
                      distanceToSegment(at(0.5 * (tm + tb)), a, b) <= tolerance_;
    if (flat || depth >= kMaxDepth) {
      out.push_back(b);
      ts.push_back(tb);
      return;
    }
    subdivide(ta, a, tm, m, depth + 1, out, ts);
    subdivide(tm, m, tb, b, depth + 1, out, ts);
  }

  const TopoDS_Edge& edge_;
  Handle(Geom2d_Curve) curve_;
  TrimPoints& points_;
  double tolerance_;
};

struct Loop {
  std::vector<glm::dvec2> points;
  std::vector<TrimCoedge> coedges;
};

// Each edge's points but the first join the loop: its first is the previous edge's last (they meet
// within the edges' tolerance), so consecutive coedges share that point.
Loop wireLoop(const TopoDS_Wire& wire, const TopoDS_Face& face, TrimPoints& points, double tolerance) {
  Loop loop;
  for (BRepTools_WireExplorer edges(wire, face); edges.More(); edges.Next()) {
    const TopoDS_Edge& edge = edges.Current();
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) curve = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (curve.IsNull()) throw ConversionError("an edge of the face has no curve on its surface (p-curve)");
    const bool reversed = edge.Orientation() == TopAbs_REVERSED;
    const EdgeFlattener flattener(edge, curve, points, tolerance);
    const double from = reversed ? last : first, to = reversed ? first : last;
    if (loop.points.empty()) loop.points.push_back(flattener.at(from));
    TrimCoedge& coedge = loop.coedges.emplace_back();
    coedge.edge = edge;
    coedge.start = static_cast<int>(loop.points.size()) - 1;
    coedge.t.push_back(from);
    flattener.append(from, to, loop.points, coedge.t);
  }
  // Consecutive edges meet within their tolerance: the last point closes the loop (the last coedge
  // then ends at point 0, its index modulo the point count).
  if (loop.points.size() > 1 && glm::length(loop.points.back() - loop.points.front()) <= tolerance) loop.points.pop_back();
  return loop;
}

// The loop the other way round, point 0 kept first (so a closed loop's coedges still begin and end
// there): point i becomes point (n - i) mod n, the coedges reversed in order and in parameter.
void reverseLoop(Loop& loop) {
  const int n = static_cast<int>(loop.points.size());
  std::reverse(loop.points.begin() + 1, loop.points.end());
  std::reverse(loop.coedges.begin(), loop.coedges.end());
  for (TrimCoedge& coedge : loop.coedges) {
    const int end = coedge.start + static_cast<int>(coedge.t.size()) - 1;  // at most n
    coedge.start = ((n - end) % n + n) % n;
    std::reverse(coedge.t.begin(), coedge.t.end());
  }
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

FaceTrim faceTrimLoops(const TopoDS_Face& face, TrimPoints& points, double tolerance) {
  const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  const TopoDS_Wire outer = BRepTools::OuterWire(forward);
  std::vector<Loop> outers, holes;
  for (TopExp_Explorer wires(forward, TopAbs_WIRE); wires.More(); wires.Next()) {
    const TopoDS_Wire& wire = TopoDS::Wire(wires.Current());
    Loop loop = wireLoop(wire, forward, points, tolerance);
    if (loop.points.size() < 3) throw ConversionError("a wire of the face gives fewer than 3 trim points");
    const bool isOuter = wire.IsSame(outer);
    if ((signedArea(loop.points) > 0.0) != isOuter) reverseLoop(loop);
    (isOuter ? outers : holes).push_back(std::move(loop));
  }
  if (outers.size() != 1) throw ConversionError("the face has no outer wire");
  FaceTrim result;
  result.trim.tolerance = tolerance;
  for (std::vector<Loop>* loops : {&outers, &holes})
    for (Loop& loop : *loops) {
      result.trim.loops.push_back(std::move(loop.points));
      result.coedges.push_back(std::move(loop.coedges));
    }
  return result;
}

}  // namespace shapespline::cad
