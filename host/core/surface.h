#pragma once
// Surface evaluation on the CPU in fp64: α-EB surfaces (docs/math.md §5), plain tensor surfaces of every
// uniform family (§6) and knot-vector B-spline surfaces (§10.1 via core/bspline.h).
//
// Two tiers like core/curve.h. The net is stored once as the "patch net" `patchNet()` of
// netRows() x netCols() points (row-major) such that patch (i,j) reads the m_u x m_v block starting
// at row i + netOffsetU(), column j + netOffsetV(): P_{i-c+r, j-c+s} of §1/§5.2 with closed
// directions wrapped and, for α-EB, the phantom rows/columns/corners of §5.1 in place.
//
// Normals (§5.3, rendering convention; never NaN):
//  1. α-EB, (u,v) exactly at a patch corner whose vertex has α = 1: the per-patch diagonal limit
//     n = (s_u A_u) x (s_v A_v) (alphaEBCornerNormal / Surface::limitNormal).
//  2. Otherwise Q_u x Q_v. If |Q_u x Q_v| < 1e-12 |Q_u||Q_v| or a partial is exactly 0, re-evaluate
//     at the point moved towards the patch centre by δ = 2^-12 in each parameter (a parameter
//     already at 1/2 stays); if still degenerate use the base surface's C_u x C_v at the original
//     point (for plain surfaces C = Q); last resort the fixed axis +z.
// Every step normalises; `normalRule` in SurfacePoint reports which step produced the normal.
#include <shapespline/core/bspline.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/model.h>
#include <shapespline/core/span_basis.h>

#include <glm/vec3.hpp>

#include <functional>
#include <utility>
#include <vector>

namespace shapespline {

// Which rule of the normal convention produced SurfacePoint::normal (see the header comment).
enum class NormalRule { Regular, CornerLimit, Shifted, Base, FixedAxis };

// Point, first and second partials with respect to the local patch parameters (u,v) — equal to
// the global ones for uniform families (R16); the knot parameters for knot-vector B-splines —
// and the unit normal.
struct SurfacePoint {
  glm::dvec3 point{0.0}, du{0.0}, dv{0.0}, duu{0.0}, duv{0.0}, dvv{0.0}, normal{0.0, 0.0, 1.0};
  NormalRule normalRule = NormalRule::Regular;
};

// The point and first partials alone: what the list kernel (core/list_eval.h) computes when asked
// for no second partials and no normal. The same bits as SurfacePoint's fields.
struct SurfaceFirst {
  glm::dvec3 point{0.0}, du{0.0}, dv{0.0};
};
// What one list evaluation keeps from one query to the next: each direction's knot interval and
// basis (knot-vector B-splines), so that a list sorted or grouped by parameter skips the lookups.
struct SurfaceListCache {
  KnotBasisCache u, v;
};

// Inclusive patch index ranges per direction (docs/math.md §5.1, §6).
struct PatchRange {
  SpanRange u, v;
};

// ---- Raw kernels (their formulas: core/point_math.h, shared with GLSL) ------------------------

// Partials of a tensor patch sum_r sum_s B_r(u) B'_s(v) net[r*stride + s] (docs/math.md §1, §6):
// bu.count rows, bv.count columns of `net` starting at the patch's first point.
struct PatchDerivs {
  glm::dvec3 p{0.0}, u{0.0}, v{0.0}, uu{0.0}, uv{0.0}, vv{0.0};
};
void evalTensorPatch(const SpanBasis& bu, const SpanBasis& bv, const glm::dvec3* net, int stride, double u,
                     double v, PatchDerivs& out);

// evalTensorPatch's point and first partials alone, the same bits (derivatives false: the point).
SurfaceFirst evalTensorPatchFirst(const SpanBasis& bu, const SpanBasis& bv, const glm::dvec3* net, int stride, double u,
                                  double v, bool derivatives);

// One α-EB patch (docs/math.md §5.2, §5.3): net = first of the 4x4 extended points P_{i-1.., j-1..},
// corners in the order (i,j), (i,j+1), (i+1,j), (i+1,j+1) for V and alpha. `base` (optional)
// receives the base surface C_ij and its partials.
void evalAlphaEBPatch(const SpanBasis& basis, const glm::dvec3* net, int stride, const glm::dvec3 V[4],
                      const double alpha[4], double u, double v, PatchDerivs& out, PatchDerivs* base);

// The diagonal-limit normal at an α = 1 vertex P (docs/math.md §5.3), unnormalised:
// A_u = V_u - P + (1 - α_u)(node - P), A_v likewise, n = (s_u A_u) x (s_v A_v), where (V_u, α_u)
// belong to the vertex's neighbour along u inside the patch, s_u = +1 if the vertex is at local
// u = 0 and -1 at u = 1 (same for v).
glm::dvec3 alphaEBCornerNormal(const glm::dvec3& p, const glm::dvec3& node, const glm::dvec3& vU, double alphaU,
                               const glm::dvec3& vV, double alphaV, double sU, double sV);

// True when the cross product of a and b cannot give a direction (§5.3 thresholds).
bool degenerateCross(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& cross);

// a scaled by the power of two that brings its largest |component| into [1, 2); zero stays zero.
// Exact, so it changes no digit of a direction; it keeps a x b and |a x b|^2 inside fp64 for any
// finite partials (nets near 1e100 or 1e-100 overflow/underflow them otherwise).
glm::dvec3 unitScaled(const glm::dvec3& a);

// The §5.3 regular-point step on unitScaled(a) x unitScaled(b): false when degenerateCross, else
// n = the unit normal. Bit-identical to normalising a x b wherever that neither overflows nor
// underflows.
bool unitNormal(const glm::dvec3& a, const glm::dvec3& b, glm::dvec3& n);

inline constexpr double kNormalShift = 1.0 / 4096.0;        // δ = 2^-12 (§5.3)
inline constexpr double kNormalDegeneracy = 1e-12;          // |a x b| < 1e-12 |a||b| (§5.3)

// An upper bound on the patch net's size for rows x cols points, any family: a reader that
// reserves this much for the points lets Surface::create build the net in their block.
size_t netCapacity(int rows, int cols);

// The parameterization a surface of this shape has (Surface::parameterization()).
Parameterization parameterizationOf(const SurfaceShape& shape);

// The valid patches of a surface of this shape, as Surface::patches() of the surface it makes
// (§5.1 for α-EB, §1 per direction for plain families, knot intervals k-1..n for knot vectors): a
// job is laid out from the shape before, or without, reading its net.
PatchRange patchRangeOf(const SurfaceShape& shape);

// The bound Surface::create tries first for an α-EB surface (§4.2: no V can leave fp64), from the
// largest |coordinate| of the points and the smallest α instead of the built net: a net whose
// points are read as a stream is checked without being built. False means "not shown", not
// "overflows": Surface::create then checks each vertex.
bool alphaEBVerticesSurelyFinite(const SurfaceShape& shape, double pointMagnitude, double smallestAlpha);

// ---- Typed surface ------------------------------------------------------------------------------

class Surface {
 public:
  // Validates (core/validate.h, throws ModelError) and precomputes everything evaluation needs.
  static Surface create(SurfaceModel model);

  // The model without its points and weights (controlPoint(), weights(), toModel() give those): the
  // surface keeps its points only once, inside its patch net (or knotData() for knot vectors).
  const SurfaceShape& model() const { return model_; }
  // Control point P_ij, 0 <= i < rows, 0 <= j < cols (no check): the same bits as the model's.
  const glm::dvec3& controlPoint(int i, int j) const {
    if (knotVector()) return bspline_.points[static_cast<size_t>(i) * model_.cols + j];
    return net_[static_cast<size_t>(i + pointRow_) * netCols_ + (j + pointCol_)];
  }
  // f(P_ij) for every control point, row-major; no copy of the net.
  template <class F>
  void forEachControlPoint(F&& f) const {
    forEachControlRow([&f](const glm::dvec3* row, int cols) {
      for (int j = 0; j < cols; ++j) f(row[j]);
    });
  }
  // f(&P_i0, cols) for every row i in order: a row's points are contiguous in the net, so a pass
  // over every point (a hash, a bound) can run over whole rows.
  template <class F>
  void forEachControlRow(F&& f) const {
    for (int i = 0; i < model_.rows; ++i) f(&controlPoint(i, 0), model_.cols);
  }
  // A copy of the points, row-major (points[i * cols + j]).
  std::vector<glm::dvec3> controlPoints() const;
  // Knot-vector B-splines: one weight per point (empty when all are 1); empty otherwise.
  const std::vector<double>& weights() const { return bspline_.weights; }
  // The whole model again (a copy of the points): for writing it out.
  SurfaceModel toModel() const;
  // Decided once here from the family table (core/family.h); every layer dispatches on it.
  Parameterization parameterization() const { return parameterization_; }
  bool usesKnotVector() const { return knotVector(); }
  // The knot-vector B-spline itself (orders, knots, net; usesKnotVector() only).
  const BSplineSurfaceData& knotData() const { return bspline_; }

  // Valid patches per direction: §5.1 for α-EB, §1 per direction for plain families; knot-vector
  // B-splines: knot interval indices k-1..n per direction (empty intervals rejected by evaluate()).
  PatchRange patches() const { return patches_; }
  std::pair<double, double> parameterRangeU() const;
  std::pair<double, double> parameterRangeV() const;
  // Global (U,V) of patch (i,j) at local (u,v): (i+u, j+v), or the knot parameters.
  std::pair<double, double> parameterOf(int i, int j, double u, double v) const;

  // Patch (i,j) at local (u,v) in [0,1]^2: partials w.r.t. the local parameters (= global for
  // uniform families), one-sided at patch edges, and the normal by the convention above.
  // Throws std::out_of_range for a patch or (u,v) outside the valid range.
  SurfacePoint evaluate(int i, int j, double u, double v) const;
  // Global (U,V) in the parameter ranges; the patch to the right/above is used at interior joints.
  SurfacePoint evaluateAt(double U, double V) const;
  // The patch (i,j) of global (U,V) and the local (u,v) in it, as evaluateAt picks them ((U,V)
  // clamped into the ranges, no check); knot-vector B-splines: the non-empty knot intervals of
  // core/bspline.h findKnotSpan. The one lookup that CPU and GPU parameter lists share.
  void patchAt(double U, double V, int& i, int& j, double& u, double& v) const;

  // The list kernel (core/list_eval.h): evaluate() / evaluateAt() without the second partials and
  // the normal, the point alone when `derivatives` is false (du, dv left 0); the same bits and the
  // same range checks. `cache` carries the knot intervals from one query of a list to the next.
  SurfaceFirst evaluateFirst(int i, int j, double u, double v, bool derivatives, SurfaceListCache& cache) const;
  SurfaceFirst evaluateFirstAt(double U, double V, bool derivatives, SurfaceListCache& cache) const;

  // The patches of rows first..last (patch indices in u) as a surface of their own, open in u:
  // its patch (i, j) is patch (first + i, j) here and evaluates to the same bits (the same net
  // rows, V, α and bases, copied). The GPU path samples a net too large for one device buffer in
  // such bands. Not for knot-vector B-splines; throws std::invalid_argument for rows outside
  // patches().u.
  Surface patchRows(int first, int last) const;

  // The same band of a surface of `shape` built from only the point rows it reads, without the
  // whole surface: a net read from its file a window at a time is sampled band by band as its rows
  // arrive (io/streamed_bands.h). pointRow(k) is point row k (shape.cols points), alphaRow(k) its
  // α (α-EB only; not called otherwise). The shape must pass validateSurfaceShape and the values
  // read must be finite with α in (0,1] (the reader's checks); every V the band holds is checked as
  // create() checks it (ModelError naming the whole net's vertex). Throws std::invalid_argument
  // like patchRows.
  using PointRowOf = std::function<const glm::dvec3*(int row)>;
  using AlphaRowOf = std::function<const double*(int row)>;
  static Surface bandOf(const SurfaceShape& shape, int first, int last, const PointRowOf& pointRow,
                        const AlphaRowOf& alphaRow);
  // The point rows bandOf(shape, first, last, ...) reads, ascending (closed u wraps: the first
  // band of a closed net reads its last rows).
  static std::vector<int> bandPointRows(const SurfaceShape& shape, int first, int last);

  // Unit diagonal-limit normal of the α = 1 vertex at corner (cornerU, cornerV) ∈ {0,1}^2 of patch
  // (i,j), as used by evaluate() at that corner (§5.3). Throws std::logic_error when the surface is
  // not α-EB or that vertex has α != 1. Falls back like evaluate() if the limit itself degenerates.
  glm::dvec3 limitNormal(int i, int j, int cornerU, int cornerV) const;

  const SpanBasis& basisU() const { return basisU_; }
  const SpanBasis& basisV() const { return basisV_; }
  const std::vector<glm::dvec3>& patchNet() const { return net_; }
  int netRows() const { return netRows_; }
  int netCols() const { return netCols_; }
  int netOffsetU() const { return offU_; }
  int netOffsetV() const { return offV_; }

  // α-EB only (empty otherwise). extendedNet() is the patch net: entry (a,b) = P_{a-1,b-1} of §5.1,
  // (R+2 or R+3) x (C+2 or C+3), row-major with netCols() columns. alphaNodes(), alphaV() and
  // alphas() are R x C row-major (node_ij = C_ij(0,0), V_ij, α_ij); patch (i,j) uses entries
  // (i, j), (i, j+1), (i+1, j), (i+1, j+1), wrapped in closed directions.
  const std::vector<glm::dvec3>& extendedNet() const { return alphaEB() ? net_ : emptyPoints_; }
  // The nodes are not kept (a 4096² net's would take 400 MB): each is 9 products of the extended
  // net, computed when asked for. alphaNodes() computes all of them.
  glm::dvec3 alphaNode(int i, int j) const;
  std::vector<glm::dvec3> alphaNodes() const;
  // V_ij = P_ij + ((1-α)/α)(P_ij - node_ij) likewise, not kept (another 400 MB at 4096²): four per
  // patch cost less than reading them from memory would. alphaV() computes all of them.
  glm::dvec3 alphaVertex(int i, int j) const;
  std::vector<glm::dvec3> alphaV() const;
  const std::vector<double>& alphas() const { return model_.alpha; }

 private:
  Surface() = default;
  // A uniform-span surface's bases, patches, net size and offsets and node weights from its shape
  // (not model_, not the net), and its net's extended indices per direction.
  void layOut(const SurfaceShape& m, std::vector<ExtendedIndex>& eu, std::vector<ExtendedIndex>& ev);
  // α-EB: every V of the net within fp64 (§4.2), else ModelError naming vertex row
  // (firstRow + i) % wholeRows (a band names the whole net's vertex).
  void requireFiniteVertices(int firstRow, int wholeRows) const;
  // The band of patch rows first..last of this layout (of a surface shaped `whole`) without its net
  // and α, which patchRows and bandOf fill.
  Surface bandShell(const SurfaceShape& whole, int first, int last) const;
  // Point and partials without normal; `base` gets C for α-EB (= the result for plain surfaces).
  void evalPatch(int i, int j, double u, double v, PatchDerivs& out, PatchDerivs& base) const;
  SurfacePoint evalWithNormal(int i, int j, double u, double v) const;
  // evalPatch's point and first partials alone (derivatives false: the point; α-EB computes the
  // partials anyway, as its blend weights read the base partials).
  SurfaceFirst evalFirst(int i, int j, double u, double v, bool derivatives, SurfaceListCache& cache) const;
  // The range checks of evaluate() and evaluateAt() (std::out_of_range).
  void checkPatchQuery(int i, int j, double u, double v) const;
  void checkGlobalQuery(double U, double V) const;
  // patchAt, trying the knot intervals hintU, hintV first (core/bspline.h findKnotSpanFrom).
  void patchAtFrom(double U, double V, int hintU, int hintV, int& i, int& j, double& u, double& v) const;
  bool cornerLimit(int i, int j, int cu, int cv, glm::dvec3& n) const;

  SurfaceShape model_;
  SpanBasis basisU_, basisV_;
  PatchRange patches_;
  bool knotVector() const { return parameterization_ == Parameterization::KnotVector; }
  bool alphaEB() const { return parameterization_ == Parameterization::AlphaEB; }

  Parameterization parameterization_ = Parameterization::LocalSpans;
  std::vector<glm::dvec3> net_;
  int netRows_ = 0, netCols_ = 0, offU_ = 0, offV_ = 0;
  // Where P_00 sits in the net: net entry (i + pointRow_, j + pointCol_) is P_ij, bit for bit.
  int pointRow_ = 0, pointCol_ = 0;
  // The span bases at 0 (b_0..b_2; b_3(0) = 0, §2.3): node_ij's weights, α-EB only.
  double nodeWeightU_[3] = {}, nodeWeightV_[3] = {};
  std::vector<glm::dvec3> emptyPoints_;
  BSplineSurfaceData bspline_;  // knot-vector B-splines only
};

}  // namespace shapespline
