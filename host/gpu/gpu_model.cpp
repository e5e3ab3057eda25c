#include <shapespline/gpu/gpu_model.h>

#include <shapespline/core/bspline.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/shaders/layout.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace {

// The kernels' basis of a knot-vector direction: only count = order and degree = order-1.
SpanBasis knotBasis(int order) {
  SpanBasis b;
  b.count = order;
  b.degree = order - 1;
  return b;
}

// What NET holds, one REAL4 record per point: the control points of a knot-vector B-spline (for a
// rational one the homogeneous (w P, w)), else core's span point list / patch net; w = 0 where
// unused.
std::vector<glm::dvec4> netRecords(std::span<const glm::dvec3> points, const std::vector<double>& weights) {
  if (!weights.empty()) return homogeneousPoints(points, weights);
  std::vector<glm::dvec4> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) out[i] = glm::dvec4(points[i], 0.0);
  return out;
}
std::vector<glm::dvec4> netPoints(const Curve& c) {
  return c.usesKnotVector() ? netRecords(c.model().points, c.model().weights) : netRecords(c.spanPoints(), {});
}
std::vector<glm::dvec4> netPoints(const Surface& s) {
  return s.usesKnotVector() ? netRecords(s.knotData().points, s.knotData().weights) : netRecords(s.patchNet(), {});
}
// NET's bytes at `precision` and how to write them: netPoints converted; a net without weights is
// converted straight into the buffer (a band of a 4096² net took 16-80 bytes a point in arrays).
NetUpload uploadOf(std::vector<std::byte> converted) {
  auto bytes = std::make_shared<const std::vector<std::byte>>(std::move(converted));
  return {bytes->size(), [bytes](std::byte* to) { std::memcpy(to, bytes->data(), bytes->size()); }};
}
NetUpload netUpload(const Curve& c, Precision precision) { return uploadOf(toReal4(netPoints(c), precision)); }
NetUpload netUpload(const Surface& s, Precision precision) {
  if (s.usesKnotVector() && !s.weights().empty()) return uploadOf(toReal4(netPoints(s), precision));
  const std::span<const glm::dvec3> points =
      s.usesKnotVector() ? std::span(s.knotData().points) : std::span(s.patchNet());
  return {points.size() * 4 * realSize(precision),
          [points, precision](std::byte* to) { writeReal4(points, precision, to); }};
}

std::vector<double> inverseSpanLengths(const Curve& c) {
  std::vector<double> invH;
  const std::vector<double>& k = c.spanKnots();
  for (size_t s = 0; s + 1 < k.size(); ++s) invH.push_back(1.0 / (k[s + 1] - k[s]));
  return invH;
}

// VERTS: V then the nodes, one REAL4 each per α-EB vertex; a placeholder otherwise.
uint64_t vertexBufferBytes(bool alphaEB, uint64_t vertices, Precision precision) {
  return alphaEB ? 2 * vertices * 4 * realSize(precision) : 256;
}

// PARAMS values a knot direction appends (addKnotDirection): the knots, 4 per non-empty interval,
// and with knot patches a record per non-empty interval.
uint64_t knotParamCount(int order, const std::vector<double>& knots, int count, bool patches) {
  uint64_t intervals = 0;
  for (int j = order - 1; j < count; ++j) intervals += knots[j] < knots[j + 1] ? 1 : 0;
  return knots.size() + intervals * (4 + (patches ? layout::kKnotPatchStride : 0));
}

}  // namespace

ModelBufferBytes modelBufferBytes(const Curve& c, Precision precision) {
  const CurveModel& m = c.model();
  const uint64_t rs = realSize(precision);
  ModelBufferBytes b;
  b.net = (c.usesKnotVector() ? m.points.size() : c.spanPoints().size()) * 4 * rs;
  uint64_t params = layout::kParamHeader;
  if (c.usesKnotVector()) {
    params += knotParamCount(m.family.order, m.knots, int(m.points.size()), false);
  } else {
    params += m.alpha.size() + inverseSpanLengths(c).size();
  }
  b.params = params * rs;
  b.verts = vertexBufferBytes(c.parameterization() == Parameterization::AlphaEB, m.points.size(), precision);
  return b;
}

ModelBufferBytes modelBufferBytes(const Surface& s, Precision precision) {
  const SurfaceShape& m = s.model();
  const uint64_t rs = realSize(precision);
  ModelBufferBytes b;
  b.net = (s.usesKnotVector() ? s.knotData().points.size() : s.patchNet().size()) * 4 * rs;
  uint64_t params = layout::kParamHeader;
  if (s.usesKnotVector()) {
    const BSplineSurfaceData& k = s.knotData();
    params += knotParamCount(k.orderU, m.knotsU, m.rows, true) + knotParamCount(k.orderV, m.knotsV, m.cols, true);
  } else {
    params += m.alpha.size();
  }
  b.params = params * rs;
  b.verts = vertexBufferBytes(s.parameterization() == Parameterization::AlphaEB, uint64_t(m.rows) * m.cols, precision);
  return b;
}

GpuModel::GpuModel(std::shared_ptr<vk::Context> ctx, Precision precision, Parameterization parameterization)
    : ctx_(std::move(ctx)), precision_(precision), parameterization_(parameterization) {
  requirePrecision(*ctx_, precision_);
}

uint32_t GpuModel::alphaOffset() const { return layout::kParamHeader; }
size_t GpuModel::addKnotDirection(int order, const std::vector<double>& knots, int count, uint32_t& knotOffset,
                                  uint32_t& intervalOffset, uint32_t* patchOffset) {
  const uint32_t base = static_cast<uint32_t>(layout::kParamHeader + alphaCount_ + invHCount_);
  knotOffset = base + static_cast<uint32_t>(knotData_.size());
  knotData_.insert(knotData_.end(), knots.begin(), knots.end());
  intervalOffset = base + static_cast<uint32_t>(knotData_.size());
  const double lo = knots[order - 1], hi = knots[count];
  size_t intervals = 0;
  for (int j = order - 1; j < count; ++j) {
    const double a = knots[j], b = knots[j + 1];
    if (!(a < b)) continue;
    // t = 1 of interval j as core/curve.cpp and core/surface.cpp form it (a + t (b - a)); the span
    // findKnotSpan picks there is the next non-empty one at an interior knot.
    const double t = 1.0;
    const double x = a + t * (b - a);
    const int end = findKnotSpan(order, knots, count, x);
    knotData_.insert(knotData_.end(), {double(j), double(end), std::clamp(x, lo, hi), 0.0});
    ++intervals;
  }
  if (patchOffset) {
    *patchOffset = base + static_cast<uint32_t>(knotData_.size());
    for (int j = order - 1; j < count; ++j) {
      if (!(knots[j] < knots[j + 1])) continue;
      const SpanBasis b = knotIntervalBasis(order, knots, j);
      std::vector<double> record(layout::kKnotPatchStride, 0.0);
      record[0] = double(j - order + 1);
      record[1] = knots[j];
      record[2] = knots[j + 1] - knots[j];
      for (int r = 0; r < b.count; ++r)
        for (int d = 0; d <= b.degree; ++d) record[layout::kKnotPatchCoef + r * layout::kCoefStride + d] = b.coef[r][d];
      knotData_.insert(knotData_.end(), record.begin(), record.end());
    }
  }
  return intervals;
}

void GpuModel::requireUniform(const char* what) const {
  if (knotVector())
    throw std::invalid_argument(std::string(what) + ": a knot-vector B-spline has no family parameters or alpha");
}

void GpuModel::requireSameBasisSize(const SpanBasis& u, const SpanBasis& v) const {
  if (u.count != basisU_.count || v.count != basisV_.count)
    throw std::invalid_argument("setParameters: the basis size m (" + std::to_string(basisU_.count) +
                                ") is fixed by the net layout; create a new GpuCurve/GpuSurface");
}

uint32_t GpuModel::invHOffset() const {
  return invHCount_ == 0 ? layout::kNoOffset : static_cast<uint32_t>(layout::kParamHeader + alphaCount_);
}

void GpuModel::createBuffers(const NetUpload& net, std::span<const double> params) {
  const size_t rs = realSize(precision_);
  net_ = vk::Buffer::create(*ctx_, net.bytes, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "gpu.net");
  net_.uploadWith(net.bytes, net.write);
  stats_.netBytes += net.bytes;
  ++stats_.netWrites;
  params_ = vk::Buffer::create(*ctx_, params.size() * rs, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "gpu.params");
  const size_t vertBytes = vertexBufferBytes(alphaEB(), uint64_t(rows_) * cols_, precision_);
  verts_ = vk::Buffer::create(*ctx_, vertBytes, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "gpu.verts");
  writeParams(params);
}

std::vector<double> GpuModel::paramBlock(const SpanBasis& u, const SpanBasis& v, std::span<const double> alpha,
                                         std::span<const double> invH) const {
  std::vector<double> p(layout::kParamHeader + alpha.size() + invH.size() + knotData_.size(), 0.0);
  for (int r = 0; r < u.count; ++r)
    for (int d = 0; d <= u.degree; ++d) p[layout::kParamCoefU + r * layout::kCoefStride + d] = u.coef[r][d];
  for (int r = 0; r < v.count; ++r)
    for (int d = 0; d <= v.degree; ++d) p[layout::kParamCoefV + r * layout::kCoefStride + d] = v.coef[r][d];
  auto out = std::copy(alpha.begin(), alpha.end(), p.begin() + layout::kParamHeader);
  out = std::copy(invH.begin(), invH.end(), out);
  std::copy(knotData_.begin(), knotData_.end(), out);
  return p;
}

void GpuModel::writeParams(std::span<const double> params) {
  const auto bytes = toReal(params, precision_);
  params_.upload(bytes);
  stats_.paramBytes += bytes.size();
  ++stats_.paramWrites;
  if (alphaEB()) vertsDirty_ = true;
}

void GpuModel::writeChangedNetEntries(std::span<const glm::dvec4> current, std::span<const glm::dvec4> next) {
  for (size_t e = 0; e < next.size(); ++e) {
    // Bitwise, so that a change of the sign of a zero reaches the GPU too.
    if (std::memcmp(&current[e], &next[e], sizeof(glm::dvec4)) == 0) continue;
    const auto bytes = toReal4(next.subspan(e, 1), precision_);
    net_.upload(bytes, e * bytes.size());
    stats_.netBytes += bytes.size();
    ++stats_.netWrites;
    if (alphaEB()) vertsDirty_ = true;
  }
}

std::vector<glm::dvec3> GpuModel::downloadVertices(bool nodes) const {
  if (!alphaEB()) return {};
  const size_t n = size_t(rows_) * cols_, rs = realSize(precision_);
  std::vector<std::byte> bytes(n * 4 * rs);
  verts_.download(bytes, nodes ? n * 4 * rs : 0);
  std::vector<glm::dvec3> out(n);
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      if (rs == 8) {
        std::memcpy(&out[i][k], bytes.data() + (4 * i + k) * 8, 8);
      } else {
        float f;
        std::memcpy(&f, bytes.data() + (4 * i + k) * 4, 4);
        out[i][k] = f;
      }
    }
  return out;
}

// ---- GpuCurve -----------------------------------------------------------------------------------

GpuCurve::GpuCurve(std::shared_ptr<vk::Context> ctx, const Curve& curve, Precision precision)
    : GpuModel(std::move(ctx), precision, curve.parameterization()), curve_(curve) {
  const CurveModel& m = curve_.model();
  rows_ = static_cast<uint32_t>(m.points.size());
  if (knotVector()) {
    basisU_ = basisV_ = knotBasis(m.family.order);
    intervalsU_ = addKnotDirection(m.family.order, m.knots, int(m.points.size()), knotOffsetU_, intervalOffsetU_);
    knotOffsetV_ = knotOffsetU_;
    intervalOffsetV_ = intervalOffsetU_;
  } else {
    basisU_ = basisV_ = curve_.basis();
    alphaCount_ = m.alpha.size();
    invHCount_ = inverseSpanLengths(curve_).size();
  }
  rational_ = !curve_.model().weights.empty();
  createBuffers(netUpload(curve_, precision), paramsOf(curve_));
}

std::vector<double> GpuCurve::paramsOf(const Curve& c) const {
  if (c.usesKnotVector()) return paramBlock(basisU_, basisV_, {}, {});
  return paramBlock(c.basis(), c.basis(), c.model().alpha, inverseSpanLengths(c));
}

void GpuCurve::adoptParameters(Curve next) {
  requireSameBasisSize(next.basis(), next.basis());
  writeParams(paramsOf(next));
  basisU_ = basisV_ = next.basis();
  curve_ = std::move(next);
}

void GpuCurve::setLambda(double lambda) {
  FamilySpec f = model().family;
  f.lambda = lambda;
  setParameters(f);
}

void GpuCurve::setParameters(const FamilySpec& family) {
  requireUniform("setParameters");
  if (family.construction != model().family.construction)
    throw std::invalid_argument("setParameters: the construction cannot change");
  CurveModel m = model();
  m.family = family;
  adoptParameters(Curve::create(std::move(m)));
}

void GpuCurve::setAlpha(int i, double alpha) {
  if (!alphaEB()) throw std::invalid_argument("setAlpha: not an alpha_eb curve");
  if (i < 0 || i >= static_cast<int>(model().alpha.size()))
    throw std::out_of_range("setAlpha: index " + std::to_string(i));
  CurveModel m = model();
  m.alpha[i] = alpha;
  adoptParameters(Curve::create(std::move(m)));
}

void GpuCurve::setAlphas(std::span<const double> alphas) {
  if (!alphaEB()) throw std::invalid_argument("setAlphas: not an alpha_eb curve");
  CurveModel m = model();
  m.alpha.assign(alphas.begin(), alphas.end());
  adoptParameters(Curve::create(std::move(m)));
}

void GpuCurve::updateControlPoint(int i, const glm::dvec3& p) {
  if (i < 0 || i >= static_cast<int>(model().points.size()))
    throw std::out_of_range("updateControlPoint: index " + std::to_string(i));
  CurveModel m = model();
  m.points[i] = p;
  Curve next = Curve::create(std::move(m));
  writeChangedNetEntries(netPoints(curve_), netPoints(next));
  curve_ = std::move(next);
}

// ---- GpuSurface ---------------------------------------------------------------------------------

GpuSurface::GpuSurface(std::shared_ptr<vk::Context> ctx, Surface surface, Precision precision)
    : GpuModel(std::move(ctx), precision, surface.parameterization()), surface_(std::move(surface)) {
  const SurfaceShape& m = surface_.model();
  rows_ = static_cast<uint32_t>(m.rows);
  cols_ = static_cast<uint32_t>(m.cols);
  if (knotVector()) {
    // Orders as core/surface.cpp Surface::create reads them (order[1] defaults to order[0]).
    const int orderU = m.family.order, orderV = m.orderV > 0 ? m.orderV : m.family.order;
    basisU_ = knotBasis(orderU);
    basisV_ = knotBasis(orderV);
    netCols_ = cols_;
    intervalsU_ = addKnotDirection(orderU, m.knotsU, m.rows, knotOffsetU_, intervalOffsetU_, &knotPatchOffsetU_);
    intervalsV_ = addKnotDirection(orderV, m.knotsV, m.cols, knotOffsetV_, intervalOffsetV_, &knotPatchOffsetV_);
  } else {
    basisU_ = surface_.basisU();
    basisV_ = surface_.basisV();
    netCols_ = static_cast<uint32_t>(surface_.netCols());
    alphaCount_ = m.alpha.size();
  }
  rational_ = !surface_.weights().empty();
  createBuffers(netUpload(surface_, precision), paramsOf(surface_));
}

std::vector<double> GpuSurface::paramsOf(const Surface& s) const {
  if (s.usesKnotVector()) {
    std::vector<double> p = paramBlock(basisU_, basisV_, {}, {});
    p[layout::kParamKnotPatchU] = double(knotPatchOffsetU_);
    p[layout::kParamKnotPatchV] = double(knotPatchOffsetV_);
    return p;
  }
  return paramBlock(s.basisU(), s.basisV(), s.model().alpha, {});
}

void GpuSurface::adoptParameters(Surface next) {
  requireSameBasisSize(next.basisU(), next.basisV());
  writeParams(paramsOf(next));
  basisU_ = next.basisU();
  basisV_ = next.basisV();
  surface_ = std::move(next);
}

void GpuSurface::setLambda(double lambda) {
  FamilySpec f = model().family;
  f.lambda = lambda;
  setParameters(f);
}

void GpuSurface::setParameters(const FamilySpec& family) {
  requireUniform("setParameters");
  if (family.construction != model().family.construction)
    throw std::invalid_argument("setParameters: the construction cannot change");
  SurfaceModel m = surface_.toModel();
  m.family = family;
  adoptParameters(Surface::create(std::move(m)));
}

void GpuSurface::setAlpha(int i, int j, double alpha) {
  if (!alphaEB()) throw std::invalid_argument("setAlpha: not an alpha_eb surface");
  const SurfaceShape& cur = model();
  if (i < 0 || j < 0 || i >= cur.rows || j >= cur.cols)
    throw std::out_of_range("setAlpha: index (" + std::to_string(i) + "," + std::to_string(j) + ")");
  SurfaceModel m = surface_.toModel();
  m.alpha[size_t(i) * m.cols + j] = alpha;
  adoptParameters(Surface::create(std::move(m)));
}

void GpuSurface::setAlphas(std::span<const double> alphas) {
  if (!alphaEB()) throw std::invalid_argument("setAlphas: not an alpha_eb surface");
  SurfaceModel m = surface_.toModel();
  m.alpha.assign(alphas.begin(), alphas.end());
  adoptParameters(Surface::create(std::move(m)));
}

void GpuSurface::updateControlPoint(int i, int j, const glm::dvec3& p) {
  const SurfaceShape& cur = model();
  if (i < 0 || j < 0 || i >= cur.rows || j >= cur.cols)
    throw std::out_of_range("updateControlPoint: index (" + std::to_string(i) + "," + std::to_string(j) + ")");
  SurfaceModel m = surface_.toModel();
  m.points[size_t(i) * m.cols + j] = p;
  Surface next = Surface::create(std::move(m));
  writeChangedNetEntries(netPoints(surface_), netPoints(next));
  surface_ = std::move(next);
}

}  // namespace shapespline::gpu
