#pragma once
// GPU-side state of one curve or surface model (OpenSubdiv style: the evaluators in
// curve_evaluator.h / surface_evaluator.h hold pipelines, this holds data). The (extended) net is
// uploaded once; λ/μ/α changes rewrite only the small PARAMS buffer (basis coefficients + α) and
// mark the α-EB vertex pass (alpha_eb_vertices.comp, run by the next evaluation) dirty, so nodes and
// V are recomputed on the GPU without touching the net. Buffer layouts: shaders/layout.h.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace shapespline::gpu {

// Byte counters of everything written into a model's buffers (tests use them to prove that a
// parameter change never re-uploads the net).
struct UploadStats {
  uint64_t netBytes = 0, netWrites = 0;
  uint64_t paramBytes = 0, paramWrites = 0;
  uint64_t vertexPasses = 0;  // alpha_eb_vertices dispatches run for this model
};

// The bytes of the storage buffers a GpuCurve / GpuSurface of a model creates (NET, PARAMS, VERTS),
// known before any is made: the sampling layer hands a model whose largest buffer exceeds the
// device's maxStorageBufferRange to the CPU with that reason instead of failing at the bind.
struct ModelBufferBytes {
  uint64_t net = 0, params = 0, verts = 0;
  uint64_t largest() const { return std::max({net, params, verts}); }
};
ModelBufferBytes modelBufferBytes(const Curve& curve, Precision precision);
ModelBufferBytes modelBufferBytes(const Surface& surface, Precision precision);

// NET's size in bytes and the function that writes them (into the mapped buffer or a staging one).
struct NetUpload {
  size_t bytes = 0;
  std::function<void(std::byte*)> write;
};

// Buffers shared by GpuCurve and GpuSurface. Every parameterization fact comes from the core
// Curve/Surface the mirror holds; this class only lays it out in NET, PARAMS and VERTS.
class GpuModel {
 public:
  Precision precision() const { return precision_; }
  // Core's parameterization of the held model (Curve/Surface::parameterization()).
  Parameterization parameterization() const { return parameterization_; }
  bool alphaEB() const { return parameterization_ == Parameterization::AlphaEB; }
  // Knot-vector B-spline (docs/math.md §10.1): NET is the plain control net, PARAMS holds the knots and
  // the interval records of layout.h; basisU()/basisV() carry only count = order, degree = order-1.
  bool knotVector() const { return parameterization_ == Parameterization::KnotVector; }
  // A rational knot-vector B-spline (weights): NET holds the homogeneous points (w P, w).
  bool rational() const { return rational_; }
  const UploadStats& uploadStats() const { return stats_; }
  const vk::Buffer& netBuffer() const { return net_; }
  const vk::Buffer& paramBuffer() const { return params_; }
  // α-EB: V (rows*cols REAL4) then nodes (rows*cols REAL4); a 256-byte placeholder otherwise.
  const vk::Buffer& vertexBuffer() const { return verts_; }
  bool verticesDirty() const { return vertsDirty_; }
  uint32_t knotOffsetU() const { return knotOffsetU_; }
  uint32_t knotOffsetV() const { return knotOffsetV_; }
  uint32_t intervalOffsetU() const { return intervalOffsetU_; }
  uint32_t intervalOffsetV() const { return intervalOffsetV_; }
  // The held model's span bases as the kernels' specialization constants read them.
  const SpanBasis& basisU() const { return basisU_; }
  const SpanBasis& basisV() const { return basisV_; }
  uint32_t alphaOffset() const;
  uint32_t invHOffset() const;  // layout::kNoOffset without span knots
  uint32_t vertexRows() const { return rows_; }
  uint32_t vertexCols() const { return cols_; }
  uint32_t netCols() const { return netCols_; }

  // α-EB: V_ij (nodes = false) or node_ij (nodes = true) as last computed by the vertex pass, read
  // back in fp64 (debugging and tests).
  std::vector<glm::dvec3> downloadVertices(bool nodes) const;

  // Called by the evaluators after they ran the vertex pass.
  void markVerticesClean() {
    vertsDirty_ = false;
    ++stats_.vertexPasses;
  }

 protected:
  GpuModel(std::shared_ptr<vk::Context> ctx, Precision precision, Parameterization parameterization);
  void createBuffers(const NetUpload& net, std::span<const double> params);
  // The PARAMS block (a few hundred bytes) of bases u, v, α and 1/h, with the knot tail.
  std::vector<double> paramBlock(const SpanBasis& u, const SpanBasis& v, std::span<const double> alpha,
                                 std::span<const double> invH) const;
  void writeParams(std::span<const double> params);
  // Writes the entries of `next` that differ bitwise from `current` (same size: the net layout).
  void writeChangedNetEntries(std::span<const glm::dvec4> current, std::span<const glm::dvec4> next);
  // Throws std::invalid_argument when a new basis would change the net layout (basis size m).
  void requireSameBasisSize(const SpanBasis& u, const SpanBasis& v) const;
  // Appends the knots and interval records of one direction to the PARAMS tail (before
  // createBuffers), and with `patchOffset` the knot patch records (shaders/layout.h); returns the
  // number of non-empty intervals.
  size_t addKnotDirection(int order, const std::vector<double>& knots, int count, uint32_t& knotOffset,
                          uint32_t& intervalOffset, uint32_t* patchOffset = nullptr);
  void requireUniform(const char* what) const;

  std::shared_ptr<vk::Context> ctx_;
  Precision precision_;
  Parameterization parameterization_;
  vk::Buffer net_, params_, verts_;
  SpanBasis basisU_, basisV_;
  size_t alphaCount_ = 0, invHCount_ = 0;
  std::vector<double> knotData_;  // PARAMS tail of knot-vector B-splines
  uint32_t rows_ = 1, cols_ = 1, netCols_ = 1;
  bool vertsDirty_ = false;
  bool rational_ = false;
  uint32_t knotOffsetU_ = 0, knotOffsetV_ = 0, intervalOffsetU_ = 0, intervalOffsetV_ = 0;
  UploadStats stats_;
};

// The GPU mirror of one Curve: it holds that Curve and keeps NET and PARAMS equal to it. Setters
// build the changed model, validate it once through Curve::create (ModelError naming the field;
// nothing changes when it throws), adopt the new Curve and rewrite only PARAMS (λ, μ, α) or the
// changed NET entries (a control point).
class GpuCurve : public GpuModel {
 public:
  // Uploads the span point list (core/curve.h) and the parameter block; knot-vector B-splines
  // upload their control points, knots and interval records instead. Double needs shaderFloat64.
  GpuCurve(std::shared_ptr<vk::Context> ctx, const Curve& curve, Precision precision);

  // The core curve this mirrors; GPU evaluation equals its evaluation within fp32/fp64 rounding.
  const Curve& curve() const { return curve_; }
  const CurveModel& model() const { return curve_.model(); }
  SpanRange spans() const { return curve_.spans(); }
  size_t spanCount() const { return static_cast<size_t>(spans().last - spans().first + 1); }
  // Items of a grid job (core/grid_sampler.h curveGridItems): spans, or the non-empty knot intervals.
  size_t gridItemCount() const { return knotVector() ? intervalsU_ : spanCount(); }
  std::pair<double, double> parameterRange() const { return curve_.parameterRange(); }
  const std::vector<double>& spanKnots() const { return curve_.spanKnots(); }
  uint32_t netOffset() const { return static_cast<uint32_t>(curve_.spanPointOffset()); }

  // λ of ExtendedBSpline/AlphaEB/GB/UBP.
  void setLambda(double lambda);
  // Any family of the same construction and basis size (the net layout depends on m).
  void setParameters(const FamilySpec& family);
  // α-EB only; α in (0,1].
  void setAlpha(int i, double alpha);
  void setAlphas(std::span<const double> alphas);
  // Moves control point i: rewrites only the net entries that change (wrapped copies, phantom points).
  void updateControlPoint(int i, const glm::dvec3& p);

 private:
  // PARAMS of `next` uploaded, then `next` adopted (a failed upload leaves the old state).
  void adoptParameters(Curve next);
  std::vector<double> paramsOf(const Curve& c) const;

  Curve curve_;
  size_t intervalsU_ = 0;
};

// The GPU mirror of one Surface, kept equal to it like GpuCurve.
class GpuSurface : public GpuModel {
 public:
  // Uploads the patch net (core/surface.h) and the parameter block; knot-vector B-spline surfaces
  // upload their control net, knots and interval records. Double needs shaderFloat64.
  // The surface is held (moved in where the caller passes a temporary, as a band of a big net).
  GpuSurface(std::shared_ptr<vk::Context> ctx, Surface surface, Precision precision);

  const Surface& surface() const { return surface_; }
  const SurfaceShape& model() const { return surface_.model(); }
  PatchRange patches() const { return surface_.patches(); }
  size_t patchesU() const { return static_cast<size_t>(patches().u.last - patches().u.first + 1); }
  size_t patchesV() const { return static_cast<size_t>(patches().v.last - patches().v.first + 1); }
  size_t patchCount() const { return patchesU() * patchesV(); }
  // Grid items (core/grid_sampler.h surfaceGridItems): patches, or the non-empty interval pairs,
  // row-major with gridItemsV() per row. Also the tessellators' patch grid.
  size_t gridItemsU() const { return knotVector() ? intervalsU_ : patchesU(); }
  size_t gridItemsV() const { return knotVector() ? intervalsV_ : patchesV(); }
  size_t gridItemCount() const { return knotVector() ? intervalsU_ * intervalsV_ : patchCount(); }
  std::pair<double, double> parameterRangeU() const { return surface_.parameterRangeU(); }
  std::pair<double, double> parameterRangeV() const { return surface_.parameterRangeV(); }
  uint32_t netOffsetU() const { return static_cast<uint32_t>(surface_.netOffsetU()); }
  uint32_t netOffsetV() const { return static_cast<uint32_t>(surface_.netOffsetV()); }

  void setLambda(double lambda);
  void setParameters(const FamilySpec& family);
  void setAlpha(int i, int j, double alpha);
  void setAlphas(std::span<const double> alphas);  // rows*cols, row-major
  void updateControlPoint(int i, int j, const glm::dvec3& p);

 private:
  void adoptParameters(Surface next);
  std::vector<double> paramsOf(const Surface& s) const;

  Surface surface_;
  size_t intervalsU_ = 0, intervalsV_ = 0;
  uint32_t knotPatchOffsetU_ = 0, knotPatchOffsetV_ = 0;  // layout.h knot patch records
};

}  // namespace shapespline::gpu
