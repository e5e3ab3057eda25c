#include <shapespline/gpu/gpu_model.h>

#include <shapespline/core/bspline.h>
#include <shapespline/core/validate.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/shaders/layout.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace {

void checkAlpha(double a, const std::string& field) {
  if (!(a > 0.0 && a <= 1.0)) throw ModelError(field, std::to_string(a), "alpha must lie in (0, 1] (docs/math.md R13)");
}

SpanBasis surfaceBasisV(const SurfaceModel& m, const SpanBasis& u) {
  if (m.family.construction == Construction::BSpline && m.orderV > 0) return uniformBSplineSpanBasis(m.orderV);
  return u;
}

}  // namespace

GpuModel::GpuModel(std::shared_ptr<vk::Context> ctx, Precision precision)
    : ctx_(std::move(ctx)), precision_(precision) {
  requirePrecision(*ctx_, precision_);
}

uint32_t GpuModel::alphaOffset() const { return layout::kParamHeader; }
size_t GpuModel::addKnotDirection(int order, const std::vector<double>& knots, int count, uint32_t& knotOffset,
                                  uint32_t& intervalOffset) {
  const uint32_t base = static_cast<uint32_t>(layout::kParamHeader + alpha_.size() + invH_.size());
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
  return intervals;
}

void GpuModel::requireUniform(const char* what) const {
  if (knotVector_)
    throw std::invalid_argument(std::string(what) + ": a knot-vector B-spline has no family parameters or alpha");
}

uint32_t GpuModel::invHOffset() const {
  return invH_.empty() ? layout::kNoOffset : static_cast<uint32_t>(layout::kParamHeader + alpha_.size());
}

void GpuModel::createBuffers(std::span<const glm::dvec3> net, size_t alphaCount, size_t invHCount) {
  const size_t rs = realSize(precision_);
  net_ = vk::Buffer::create(*ctx_, net.size() * 4 * rs, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "gpu.net");
  const auto bytes = toReal4(net, precision_);
  net_.upload(bytes);
  stats_.netBytes += bytes.size();
  ++stats_.netWrites;
  params_ = vk::Buffer::create(*ctx_, (layout::kParamHeader + alphaCount + invHCount + knotData_.size()) * rs, vk::kStorageUsage,
                               vk::MemoryUse::DeviceLocal, "gpu.params");
  const size_t vertBytes = alphaEB_ ? 2 * size_t(rows_) * cols_ * 4 * rs : 256;
  verts_ = vk::Buffer::create(*ctx_, vertBytes, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "gpu.verts");
  writeParams();
}

void GpuModel::writeParams() {
  std::vector<double> p(layout::kParamHeader + alpha_.size() + invH_.size() + knotData_.size(), 0.0);
  for (int r = 0; r < basisU_.count; ++r)
    for (int d = 0; d <= basisU_.degree; ++d) p[layout::kParamCoefU + r * layout::kCoefStride + d] = basisU_.coef[r][d];
  for (int r = 0; r < basisV_.count; ++r)
    for (int d = 0; d <= basisV_.degree; ++d) p[layout::kParamCoefV + r * layout::kCoefStride + d] = basisV_.coef[r][d];
  std::copy(alpha_.begin(), alpha_.end(), p.begin() + layout::kParamHeader);
  std::copy(invH_.begin(), invH_.end(), p.begin() + layout::kParamHeader + alpha_.size());
  std::copy(knotData_.begin(), knotData_.end(), p.begin() + layout::kParamHeader + alpha_.size() + invH_.size());
  const auto bytes = toReal(p, precision_);
  params_.upload(bytes);
  stats_.paramBytes += bytes.size();
  ++stats_.paramWrites;
  if (alphaEB_) vertsDirty_ = true;
}

void GpuModel::writeNetEntry(size_t index, const glm::dvec3& p) {
  const glm::dvec3 one[1] = {p};
  const auto bytes = toReal4(one, precision_);
  net_.upload(bytes, index * bytes.size());
  stats_.netBytes += bytes.size();
  ++stats_.netWrites;
  if (alphaEB_) vertsDirty_ = true;
}

std::vector<glm::dvec3> GpuModel::downloadVertices(bool nodes) const {
  if (!alphaEB_) return {};
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

void GpuModel::setBases(const SpanBasis& u, const SpanBasis& v) {
  if (u.count != basisU_.count || v.count != basisV_.count)
    throw std::invalid_argument("setParameters: the basis size m (" + std::to_string(basisU_.count) +
                                ") is fixed by the net layout; create a new GpuCurve/GpuSurface");
  basisU_ = u;
  basisV_ = v;
}

// ---- GpuCurve -----------------------------------------------------------------------------------

GpuCurve::GpuCurve(std::shared_ptr<vk::Context> ctx, const Curve& curve, Precision precision)
    : GpuModel(std::move(ctx), precision),
      model_(curve.model()),
      spans_(curve.spans()),
      range_(curve.parameterRange()),
      spanKnots_(curve.spanKnots()) {
  if (curve.usesKnotVector()) {
    knotVector_ = true;
    const int order = model_.family.order, n = static_cast<int>(model_.points.size());
    basisU_ = SpanBasis{};
    basisU_.count = order;
    basisU_.degree = order - 1;
    basisV_ = basisU_;
    rows_ = static_cast<uint32_t>(n);
    intervalsU_ = addKnotDirection(order, model_.knots, n, knotOffsetU_, intervalOffsetU_);
    knotOffsetV_ = knotOffsetU_;
    intervalOffsetV_ = intervalOffsetU_;
    createBuffers(model_.points, 0, 0);
    return;
  }
  alphaEB_ = model_.family.construction == Construction::AlphaEB;
  basisU_ = basisV_ = curve.basis();
  ext_ = extendedIndices(static_cast<int>(model_.points.size()), model_.closed, alphaEB_, basisU_.count,
                         basisU_.centre, netOffset_);
  netOffset_ = curve.spanPointOffset();
  rows_ = static_cast<uint32_t>(model_.points.size());
  if (alphaEB_) alpha_ = model_.alpha;
  for (size_t s = 0; s + 1 < curve.spanKnots().size(); ++s)
    invH_.push_back(1.0 / (curve.spanKnots()[s + 1] - curve.spanKnots()[s]));
  createBuffers(curve.spanPoints(), alpha_.size(), invH_.size());
}

void GpuCurve::setLambda(double lambda) {
  FamilySpec f = model_.family;
  f.lambda = lambda;
  setParameters(f);
}

void GpuCurve::setParameters(const FamilySpec& family) {
  requireUniform("setParameters");
  if (family.construction != model_.family.construction)
    throw std::invalid_argument("setParameters: the construction cannot change");
  validateFamily(family, 0, false);
  const SpanBasis b = makeSpanBasis(family);
  setBases(b, b);
  model_.family = family;
  writeParams();
}

void GpuCurve::setAlpha(int i, double alpha) {
  if (!alphaEB_) throw std::invalid_argument("setAlpha: not an alpha_eb curve");
  if (i < 0 || i >= static_cast<int>(alpha_.size())) throw std::out_of_range("setAlpha: index " + std::to_string(i));
  checkAlpha(alpha, "alpha[" + std::to_string(i) + "]");
  alpha_[i] = model_.alpha[i] = alpha;
  writeParams();
}

void GpuCurve::setAlphas(std::span<const double> alphas) {
  if (!alphaEB_) throw std::invalid_argument("setAlphas: not an alpha_eb curve");
  if (alphas.size() != alpha_.size()) throw std::invalid_argument("setAlphas: expected one value per point");
  for (size_t i = 0; i < alphas.size(); ++i) checkAlpha(alphas[i], "alpha[" + std::to_string(i) + "]");
  alpha_.assign(alphas.begin(), alphas.end());
  model_.alpha = alpha_;
  writeParams();
}

void GpuCurve::updateControlPoint(int i, const glm::dvec3& p) {
  if (i < 0 || i >= static_cast<int>(model_.points.size()))
    throw std::out_of_range("updateControlPoint: index " + std::to_string(i));
  model_.points[i] = p;
  if (knotVector_) {
    writeNetEntry(static_cast<size_t>(i), p);
    return;
  }
  for (size_t e = 0; e < ext_.size(); ++e) {
    const ExtendedIndex& x = ext_[e];
    if (x.i0 != i && !(x.w1 != 0.0 && x.i1 == i)) continue;
    const glm::dvec3 v = x.w1 == 0.0 ? model_.points[x.i0] : x.w0 * model_.points[x.i0] + x.w1 * model_.points[x.i1];
    writeNetEntry(e, v);
  }
}

// ---- GpuSurface ---------------------------------------------------------------------------------

GpuSurface::GpuSurface(std::shared_ptr<vk::Context> ctx, const Surface& surface, Precision precision)
    : GpuModel(std::move(ctx), precision),
      model_(surface.model()),
      patches_(surface.patches()),
      rangeU_(surface.parameterRangeU()),
      rangeV_(surface.parameterRangeV()) {
  if (surface.usesKnotVector()) {
    knotVector_ = true;
    // Orders as core/surface.cpp Surface::create reads them (order[1] defaults to order[0]).
    const int orderU = model_.family.order, orderV = model_.orderV > 0 ? model_.orderV : model_.family.order;
    basisU_ = SpanBasis{};
    basisU_.count = orderU;
    basisU_.degree = orderU - 1;
    basisV_ = SpanBasis{};
    basisV_.count = orderV;
    basisV_.degree = orderV - 1;
    rows_ = static_cast<uint32_t>(model_.rows);
    cols_ = static_cast<uint32_t>(model_.cols);
    netCols_ = cols_;
    intervalsU_ = addKnotDirection(orderU, model_.knotsU, model_.rows, knotOffsetU_, intervalOffsetU_);
    intervalsV_ = addKnotDirection(orderV, model_.knotsV, model_.cols, knotOffsetV_, intervalOffsetV_);
    createBuffers(model_.points, 0, 0);
    return;
  }
  alphaEB_ = model_.family.construction == Construction::AlphaEB;
  basisU_ = surface.basisU();
  basisV_ = surface.basisV();
  extU_ = extendedIndices(model_.rows, model_.closedU, alphaEB_, basisU_.count, basisU_.centre, offU_);
  extV_ = extendedIndices(model_.cols, model_.closedV, alphaEB_, basisV_.count, basisV_.centre, offV_);
  offU_ = surface.netOffsetU();
  offV_ = surface.netOffsetV();
  rows_ = static_cast<uint32_t>(model_.rows);
  cols_ = static_cast<uint32_t>(model_.cols);
  netCols_ = static_cast<uint32_t>(surface.netCols());
  if (alphaEB_) alpha_ = model_.alpha;
  createBuffers(surface.patchNet(), alpha_.size(), 0);
}

void GpuSurface::setLambda(double lambda) {
  FamilySpec f = model_.family;
  f.lambda = lambda;
  setParameters(f);
}

void GpuSurface::setParameters(const FamilySpec& family) {
  requireUniform("setParameters");
  if (family.construction != model_.family.construction)
    throw std::invalid_argument("setParameters: the construction cannot change");
  validateFamily(family, model_.orderV, true);
  const SpanBasis b = makeSpanBasis(family);
  SurfaceModel m = model_;
  m.family = family;
  setBases(b, surfaceBasisV(m, b));
  model_.family = family;
  writeParams();
}

void GpuSurface::setAlpha(int i, int j, double alpha) {
  if (!alphaEB_) throw std::invalid_argument("setAlpha: not an alpha_eb surface");
  if (i < 0 || j < 0 || i >= model_.rows || j >= model_.cols)
    throw std::out_of_range("setAlpha: index (" + std::to_string(i) + "," + std::to_string(j) + ")");
  checkAlpha(alpha, "alpha[" + std::to_string(i) + "][" + std::to_string(j) + "]");
  alpha_[size_t(i) * model_.cols + j] = model_.alpha[size_t(i) * model_.cols + j] = alpha;
  writeParams();
}

void GpuSurface::setAlphas(std::span<const double> alphas) {
  if (!alphaEB_) throw std::invalid_argument("setAlphas: not an alpha_eb surface");
  if (alphas.size() != alpha_.size()) throw std::invalid_argument("setAlphas: expected rows*cols values");
  for (size_t i = 0; i < alphas.size(); ++i) checkAlpha(alphas[i], "alpha[" + std::to_string(i) + "]");
  alpha_.assign(alphas.begin(), alphas.end());
  model_.alpha = alpha_;
  writeParams();
}

void GpuSurface::updateControlPoint(int i, int j, const glm::dvec3& p) {
  if (i < 0 || j < 0 || i >= model_.rows || j >= model_.cols)
    throw std::out_of_range("updateControlPoint: index (" + std::to_string(i) + "," + std::to_string(j) + ")");
  model_.points[size_t(i) * model_.cols + j] = p;
  if (knotVector_) {
    writeNetEntry(size_t(i) * model_.cols + j, p);
    return;
  }
  const SurfaceModel& m = model_;
  auto uses = [](const ExtendedIndex& x, int k) { return x.i0 == k || (x.w1 != 0.0 && x.i1 == k); };
  for (size_t a = 0; a < extU_.size(); ++a) {
    if (!uses(extU_[a], i)) continue;
    for (size_t b = 0; b < extV_.size(); ++b) {
      if (!uses(extV_[b], j)) continue;
      const ExtendedIndex& x = extU_[a];
      const ExtendedIndex& y = extV_[b];
      // Same operation order as core/surface.cpp (rows first, then columns of the rows).
      auto rowPoint = [&](int r) { return y.w1 == 0.0 ? m.at(r, y.i0) : y.w0 * m.at(r, y.i0) + y.w1 * m.at(r, y.i1); };
      writeNetEntry(a * netCols_ + b, x.w1 == 0.0 ? rowPoint(x.i0) : x.w0 * rowPoint(x.i0) + x.w1 * rowPoint(x.i1));
    }
  }
}

}  // namespace shapespline::gpu
