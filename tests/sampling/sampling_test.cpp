// The sampling layer (host/sampling): which path a request takes, the fallbacks and their reasons,
// DeviceError when the device is required, the report's precisions, the exact net scaling round
// trip, and knot-vector B-splines on the GPU, each against the CPU fp64 core.
//
// Tolerances (tests/support/tolerances.h), scale = bounding-box diagonal of the net: points
// 4 kFp32Rel * scale (the fp32 kernels' few ulps); first derivatives the same times 8 k / h for
// knot-vector models of order k and smallest knot interval h (tests/gpu/gpu_bspline_test.cpp), and
// times 16 for the uniform-span constructions (Σ|B'| of their bases stays below 8).
#include <gtest/gtest.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/io/model_json.h>
#include <shapespline/sampling/gpu_limits.h>
#include <shapespline/sampling/net_scale.h>
#include <shapespline/sampling/session.h>
#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

using sampling::DeviceKind;
using sampling::DeviceRequest;

template <class M>
M exampleModel(const char* name) {
  return std::get<M>(io::loadModelFile(std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/models/" + name));
}

double bboxDiag(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

double smallestInterval(const std::vector<double>& knots) {
  double h = 1.0;
  for (size_t i = 1; i < knots.size(); ++i)
    if (knots[i] > knots[i - 1]) h = std::min(h, knots[i] - knots[i - 1]);
  return h;
}

// One plane of a grid job, gathered over its chunks (as fp64).
std::vector<double> gathered(sampling::Session& session, const Surface& s, const DeviceRequest& request, Field field,
                             sampling::Report* report = nullptr) {
  std::vector<double> out;
  GridSpec grid;
  grid.samplesU = grid.samplesV = 5;
  grid.itemCount = surfaceGridItems(s).size();
  const sampling::Report r = session.sampleGrid(s, request, grid, fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(field),
                                                [&](const GridChunk& c) {
                                                  for (size_t p = 0; p < c.pointCount(); ++p)
                                                    for (int a = 0; a < 3; ++a) out.push_back(c.coord(field, p, a));
                                                });
  if (report) *report = r;
  return out;
}

void expectNear(const std::vector<double>& expect, const std::vector<double>& got, double tol, const std::string& what) {
  ASSERT_EQ(expect.size(), got.size()) << what;
  int failures = 0;
  for (size_t i = 0; i < expect.size(); ++i) {
    if (!(std::abs(expect[i] - got[i]) <= tol) && failures++ < 5)
      ADD_FAILURE() << what << " value " << i << ": expected " << expect[i] << " got " << got[i] << " tol " << tol;
  }
}

// ---- without a device ------------------------------------------------------------------------

vk::ContextOptions noSuchDevice() {
  vk::ContextOptions o;
  o.deviceName = "no device has this name";
  return o;
}

TEST(SamplingNetScale, ExponentBringsLargeAndTinyNetsIntoRange) {
  using Net = std::vector<glm::dvec3>;
  EXPECT_EQ(sampling::netScale(Net{{1.0, -3.0, 0.5}}, Precision::Float), 0);
  EXPECT_EQ(sampling::netScale(Net{{1e30, 0.0, 0.0}}, Precision::Float), -std::ilogb(1e30));
  EXPECT_EQ(sampling::netScale(Net{{1e30, 0.0, 0.0}}, Precision::Double), 0);  // inside fp64's band
  EXPECT_EQ(sampling::netScale(Net{{0.0, 3e-310, 0.0}}, Precision::Double), -std::ilogb(3e-310));
  EXPECT_EQ(sampling::netScale(Net{}, Precision::Float), 0);
}

TEST(SamplingPath, CpuRequestComputesFp64AndNamesTheCpu) {
  sampling::Session session(noSuchDevice());
  const Curve c = Curve::create(exampleModel<CurveModel>("open_aeb.json"));
  const sampling::Report r = session.plan(c, {DeviceKind::Cpu, Precision::Float, true});
  EXPECT_FALSE(r.gpu);
  EXPECT_EQ(r.device, "cpu");
  EXPECT_TRUE(r.fallbacks.empty());
  EXPECT_EQ(r.computedPrecision, Precision::Double);
  EXPECT_EQ(r.outputPrecision, Precision::Float);
}

TEST(SamplingPath, NoDeviceFallsBackWithTheReasonOrRefusesWhenRequired) {
  sampling::Session session(noSuchDevice());
  const Curve c = Curve::create(exampleModel<CurveModel>("open_aeb.json"));
  for (DeviceKind kind : {DeviceKind::Auto, DeviceKind::Vulkan}) {
    const sampling::Report r = session.plan(c, {kind, Precision::Float, false});
    EXPECT_FALSE(r.gpu);
    EXPECT_EQ(r.device, "cpu");
    ASSERT_EQ(r.fallbacks.size(), 1u);
    EXPECT_NE(r.fallbacks[0].find("no Vulkan device (no usable device name contains"), std::string::npos)
        << r.fallbacks[0];
    EXPECT_EQ(r.computedPrecision, Precision::Double);
    try {
      session.plan(c, {kind, Precision::Float, true});
      ADD_FAILURE() << "require: no DeviceError";
    } catch (const sampling::DeviceError& e) {
      EXPECT_TRUE(e.fallbackRefused());
      EXPECT_NE(std::string(e.what()).find("no Vulkan device"), std::string::npos) << e.what();
    }
  }
  // The fallback's grid is the CPU sampler's, chunk for chunk.
  const Surface s = Surface::create(exampleModel<SurfaceModel>("surface_aeb.json"));
  const std::vector<double> viaLayer = gathered(session, s, {DeviceKind::Auto, Precision::Double, false}, Field::Normal);
  std::vector<double> direct;
  GridSpec grid;
  grid.samplesU = grid.samplesV = 5;
  grid.itemCount = surfaceGridItems(s).size();
  sampleSurfaceGrid(s, grid, fieldBit(Field::Normal), [&](const GridChunk& c) {
    for (size_t p = 0; p < c.pointCount(); ++p)
      for (int a = 0; a < 3; ++a) direct.push_back(c.coord(Field::Normal, p, a));
  });
  EXPECT_EQ(viaLayer, direct);
}

// planDevice (a job that samples nothing, issue 31): the device part of plan() alone, with its
// fallback and refusal.
TEST(SamplingPath, PlanDeviceFallsBackAndRefusesAsPlanDoes) {
  sampling::Session session(noSuchDevice());
  const sampling::Report cpu = session.planDevice({DeviceKind::Cpu, Precision::Float, true});
  EXPECT_FALSE(cpu.gpu);
  EXPECT_EQ(cpu.device, "cpu");
  EXPECT_TRUE(cpu.fallbacks.empty());
  EXPECT_EQ(cpu.outputPrecision, Precision::Float);
  const Curve c = Curve::create(exampleModel<CurveModel>("open_aeb.json"));
  const sampling::Report planned = session.plan(c, {DeviceKind::Auto, Precision::Float, false});
  const sampling::Report device = session.planDevice({DeviceKind::Auto, Precision::Float, false});
  EXPECT_FALSE(device.gpu);
  EXPECT_EQ(device.device, "cpu");
  EXPECT_EQ(device.fallbacks, planned.fallbacks);
  EXPECT_EQ(device.computedPrecision, Precision::Double);
  EXPECT_THROW(session.planDevice({DeviceKind::Vulkan, Precision::Float, true}), sampling::DeviceError);
}

// ---- on the GPU (validation on) --------------------------------------------------------------

// prepare() only moves the context's creation earlier: the plans that follow report what they would
// have, the fallback and the refusal without a device included.
TEST(SamplingPath, PreparedSessionPlansAsAPlainOne) {
  const Curve c = Curve::create(exampleModel<CurveModel>("open_aeb.json"));
  sampling::Session prepared(noSuchDevice());
  prepared.prepare({DeviceKind::Vulkan, Precision::Float, true});
  prepared.prepare({DeviceKind::Vulkan, Precision::Float, true});  // again while the first runs: nothing
  const sampling::Report r = prepared.plan(c, {DeviceKind::Auto, Precision::Float, false});
  EXPECT_FALSE(r.gpu);
  ASSERT_EQ(r.fallbacks.size(), 1u);
  EXPECT_NE(r.fallbacks[0].find("no Vulkan device (no usable device name contains"), std::string::npos) << r.fallbacks[0];
  EXPECT_THROW(prepared.plan(c, {DeviceKind::Vulkan, Precision::Float, true}), sampling::DeviceError);
  sampling::Session cpu(noSuchDevice());
  cpu.prepare({DeviceKind::Cpu, Precision::Float, true});
  EXPECT_EQ(cpu.vulkanContext(), nullptr);  // a CPU request creates nothing
  { sampling::Session dropped(noSuchDevice()); dropped.prepare({DeviceKind::Auto, Precision::Double, false}); }
}

class SamplingGpu : public VulkanTest {};

TEST_F(SamplingGpu, PreparedSessionPlansOnItsOwnDevice) {
  vk::ContextOptions options;
  options.validation = true;
  options.persistentPipelineCache = false;
  options.deviceName = ctx().deviceName();
  sampling::Session session(options);
  session.prepare({DeviceKind::Vulkan, Precision::Float, true});
  EXPECT_EQ(session.vulkanContext(), nullptr);  // not before a plan collects it
  const Surface s = Surface::create(exampleModel<SurfaceModel>("surface_aeb.json"));
  const sampling::Report r = session.plan(s, {DeviceKind::Vulkan, Precision::Float, true});
  EXPECT_TRUE(r.gpu);
  EXPECT_EQ(r.device, ctx().deviceName());
  ASSERT_NE(session.vulkanContext(), nullptr);
  EXPECT_TRUE(session.vulkanContext()->validationMessages().empty())
      << formatValidationMessages(session.vulkanContext()->validationMessages());
  // Its grid is the shared context's, bit for bit.
  sampling::Session shared(ctx_);
  const DeviceRequest request{DeviceKind::Vulkan, Precision::Float, true};
  EXPECT_EQ(gathered(session, s, request, Field::Point), gathered(shared, s, request, Field::Point));
}

TEST_F(SamplingGpu, AutoAndVulkanUseTheDeviceInTheRequestedPrecision) {
  sampling::Session session(ctx_);
  const Curve c = Curve::create(exampleModel<CurveModel>("open_aeb.json"));
  for (DeviceKind kind : {DeviceKind::Auto, DeviceKind::Vulkan}) {
    const sampling::Report r = session.plan(c, {kind, Precision::Float, true});
    EXPECT_TRUE(r.gpu);
    EXPECT_EQ(r.device, ctx().deviceName());
    EXPECT_TRUE(r.fallbacks.empty());
    EXPECT_EQ(r.computedPrecision, Precision::Float);
    EXPECT_EQ(r.netScaleExponent, 0);
  }
  EXPECT_FALSE(session.plan(c, {DeviceKind::Cpu, Precision::Float, true}).gpu);
  // planDevice names the same device in the same precision.
  const sampling::Report d = session.planDevice({DeviceKind::Vulkan, Precision::Float, true});
  EXPECT_TRUE(d.gpu);
  EXPECT_EQ(d.device, ctx().deviceName());
  EXPECT_EQ(d.computedPrecision, Precision::Float);
}

TEST_F(SamplingGpu, ModelBeyondTheKernelsFallsBackWithItsReason) {
  sampling::Session session(ctx_);
  CurveModel m = exampleModel<CurveModel>("open_aeb.json");
  std::fill(m.alpha.begin(), m.alpha.end(), 1e-31);
  const Curve c = Curve::create(m);
  const sampling::Report r = session.plan(c, {DeviceKind::Auto, Precision::Float, false});
  EXPECT_FALSE(r.gpu);
  ASSERT_EQ(r.fallbacks.size(), 1u);
  EXPECT_EQ(r.fallbacks[0], *sampling::gpuLimitation(c, Precision::Float));
  EXPECT_NE(r.fallbacks[0].find("alpha = 1e-31 is below 1e-30"), std::string::npos) << r.fallbacks[0];
  EXPECT_THROW(session.plan(c, {DeviceKind::Vulkan, Precision::Float, true}), sampling::DeviceError);
  EXPECT_TRUE(session.plan(c, {DeviceKind::Vulkan, Precision::Double, true}).gpu);  // fp64 represents it
}

// A model whose largest device buffer exceeds one storage binding (maxStorageBufferRange: 128 MiB
// on lavapipe) goes to the CPU with the sizes in the reason, and is refused when the device is
// required; one vertex fewer than the limit allows stays on the GPU. An α-EB curve, the cheapest
// such model: its VERTS holds 2 REAL4 per vertex.
TEST_F(SamplingGpu, ModelBeyondOneStorageBindingFallsBackWithTheSizes) {
  const uint64_t range = ctx().limits().maxStorageBufferRange;
  const Precision p = Precision::Float;
  const uint64_t perVertex = 2 * 4 * 4;
  if (range / perVertex > (uint64_t{1} << 24)) GTEST_SKIP() << "maxStorageBufferRange " << range << " needs too large a model";
  CurveModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.dimension = 2;
  const size_t fits = static_cast<size_t>(range / perVertex);
  m.points.resize(fits + 1);
  for (size_t i = 0; i < m.points.size(); ++i) m.points[i] = {double(i), std::sin(0.01 * double(i)), 0.0};
  m.alpha.assign(m.points.size(), 0.5);
  sampling::Session session(ctx_);
  {
    const Curve c = Curve::create(m);
    ASSERT_GT(gpu::modelBufferBytes(c, p).largest(), range);
    const sampling::Report r = session.plan(c, {DeviceKind::Auto, p, false});
    EXPECT_FALSE(r.gpu);
    ASSERT_EQ(r.fallbacks.size(), 1u);
    EXPECT_NE(r.fallbacks[0].find("-byte device buffer in fp32, over the " + std::to_string(range) +
                                  "-byte limit of Vulkan device"),
              std::string::npos)
        << r.fallbacks[0];
    EXPECT_NE(r.fallbacks[0].find("only grid jobs are split into bands"), std::string::npos) << r.fallbacks[0];
    // A curve's grid is not split either.
    DeviceRequest grid{DeviceKind::Auto, p, false};
    grid.grid = true;
    EXPECT_FALSE(session.plan(c, grid).gpu);
    EXPECT_THROW(session.plan(c, {DeviceKind::Vulkan, p, true}), sampling::DeviceError);
  }
  m.points.resize(fits);
  m.alpha.resize(fits);
  const Curve c = Curve::create(m);
  EXPECT_LE(gpu::modelBufferBytes(c, p).largest(), range);
  EXPECT_TRUE(session.plan(c, {DeviceKind::Auto, p, false}).gpu);
}

// A surface net over the session's buffer limit (or its band budget) is sampled on the GPU in bands
// of patch rows (Surface::patchRows), each band its own mirror: the chunks are bit for bit those of the whole
// net on the device (same kernels, same inputs), for whole jobs and item ranges that start and end
// inside bands; list jobs and knot-vector nets go to the CPU with the reason.
TEST_F(SamplingGpu, NetsOverTheBufferLimitAreSampledInBandsWithTheSameBits) {
  SurfaceModel open = wavyNet(FamilySpec{Construction::AlphaEB, 5, 0, -1.0, {}}, 9, true);
  open.alpha[3 * 9 + 4] = open.alpha[8 * 9 + 8] = 1.0;
  SurfaceModel closedU = open;
  closedU.closedU = true;
  SurfaceModel xu = wavyNet(FamilySpec{Construction::ExtendedBSpline, 5, 0, 0.5, {}}, 10, false);
  xu.closedU = xu.closedV = true;
  std::vector<Precision> precisions = {Precision::Float};
  if (ctx().supportsFloat64()) precisions.push_back(Precision::Double);
  const FieldMask fields = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dvv) | fieldBit(Field::Normal);
  for (const auto& [name, model] : {std::pair{"open alpha_eb", open}, {"alpha_eb closed in u", closedU}, {"closed xu-wang", xu}}) {
    const Surface s = Surface::create(model);
    const size_t items = surfaceGridItems(s).size();
    for (Precision p : precisions) {
      SCOPED_TRACE(std::string(name) + (p == Precision::Double ? " fp64" : " fp32"));
      DeviceRequest request{DeviceKind::Vulkan, p, true};
      request.grid = true;
      sampling::Session whole(ctx_), bands(ctx_), budget(ctx_);
      // Room for about three patch rows: the net is the largest buffer. `budget` splits the net
      // because of its band budget, under the device's limits.
      const gpu::ModelBufferBytes all = gpu::modelBufferBytes(s, p);
      const uint64_t threeRows = all.largest() * 4 / (s.patches().u.last - s.patches().u.first + 1);
      bands.setMaxBufferBytes(threeRows);
      budget.setBandBudgetBytes(threeRows);
      const sampling::Report r = bands.plan(s, request);
      ASSERT_TRUE(r.gpu);
      EXPECT_GE(r.bandRows, 1);
      EXPECT_LT(r.bandRows, s.patches().u.last - s.patches().u.first + 1);
      EXPECT_EQ(budget.plan(s, request).bandRows, r.bandRows);
      EXPECT_EQ(whole.plan(s, request).bandRows, 0);
      // {9, 4}: inside one patch row, so its band ends before the bands' size (the job's last row).
      for (const auto& range : {std::pair<size_t, size_t>{0, 0}, {5, 17}, {9, 4}, {items - 3, 3}}) {
        const size_t first = range.first, count = range.second;  // captured below: no structured binding (clang 15)
        GridSpec g;
        g.samplesU = 3;
        g.samplesV = 4;
        g.firstItem = first;
        g.itemCount = count;
        // Each field's bytes over the whole job (chunks may be cut differently), and where each
        // chunk starts.
        auto run = [&](sampling::Session& session) {
          std::vector<std::string> planes(4);
          size_t firstItem = SIZE_MAX, points = 0;
          session.sampleGrid(s, request, g, fields, [&](const GridChunk& c) {
            if (firstItem == SIZE_MAX) firstItem = c.firstItem;
            EXPECT_EQ(c.firstItem * c.pointsPerItem + c.firstItemPoint(), first * c.pointsPerItem + points);
            points += c.pointCount();
            const size_t size = c.pointCount() * 3 * (p == Precision::Double ? 8 : 4);
            int k = 0;
            for (Field f : {Field::Point, Field::Du, Field::Dvv, Field::Normal})
              planes[size_t(k++)].append(static_cast<const char*>(c.planes[size_t(f)]), size);
          });
          return std::pair{firstItem, planes};
        };
        const auto [firstWhole, bytesWhole] = run(whole);
        const auto [firstBands, bytesBands] = run(bands);
        const auto [firstBudget, bytesBudget] = run(budget);
        EXPECT_EQ(firstBands, first);
        EXPECT_EQ(firstBudget, first);
        EXPECT_EQ(firstWhole, first);
        for (size_t k = 0; k < 4; ++k) {
          EXPECT_TRUE(bytesBands[k] == bytesWhole[k]) << "items from " << first << ": field " << k << " differs";
          EXPECT_TRUE(bytesBudget[k] == bytesWhole[k]) << "items from " << first << ": field " << k << " differs";
        }
      }
      // A list job needs the whole net on the device.
      DeviceRequest list = request;
      list.grid = false;
      list.require = false;
      const sampling::Report lr = bands.plan(s, list);
      EXPECT_FALSE(lr.gpu);
      ASSERT_EQ(lr.fallbacks.size(), 1u);
      EXPECT_NE(lr.fallbacks[0].find("only grid jobs are split into bands"), std::string::npos) << lr.fallbacks[0];
      // The band budget is no limit: a list job on that session runs on the GPU, whole.
      const sampling::Report br = budget.plan(s, list);
      EXPECT_TRUE(br.gpu);
      EXPECT_EQ(br.bandRows, 0);
    }
  }
  // Knot-vector nets are not split.
  sampling::Session tiny(ctx_);
  tiny.setMaxBufferBytes(64);
  DeviceRequest grid{DeviceKind::Auto, Precision::Float, false};
  grid.grid = true;
  const sampling::Report kr = tiny.plan(Surface::create(nurbsTorus(3.0, 1.0)), grid);
  EXPECT_FALSE(kr.gpu);
  ASSERT_EQ(kr.fallbacks.size(), 1u);
  EXPECT_NE(kr.fallbacks[0].find("knot-vector nets and curves are not split into bands"), std::string::npos) << kr.fallbacks[0];
  // Over the band budget alone, they stay on the GPU, whole.
  sampling::Session small(ctx_);
  small.setBandBudgetBytes(64);
  const sampling::Report sr = small.plan(Surface::create(nurbsTorus(3.0, 1.0)), grid);
  EXPECT_TRUE(sr.gpu);
  EXPECT_EQ(sr.bandRows, 0);
}

// More knots than fp32 PARAMS indices address exactly: the fp32 GPU path falls back, naming them;
// fp64 takes them.
TEST(GpuLimits, KnotCountBeyondFp32IndexingIsNamed) {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = m.orderV = 2;
  m.rows = int(sampling::kMaxKnotsGpuFloat);  // rows + order knots along u
  m.cols = 2;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points.push_back({double(i), double(j), 0.0});
  for (int i = 0; i < m.rows + 2; ++i) m.knotsU.push_back(double(i));
  m.knotsV = {0, 0, 1, 1};
  const auto why = sampling::gpuLimitation(Surface::create(m), Precision::Float);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("knots[0]: 65538 knots"), std::string::npos) << *why;
  EXPECT_FALSE(sampling::gpuLimitation(Surface::create(m), Precision::Double));
  m.rows -= 2;
  m.points.resize(size_t(m.rows) * m.cols);
  m.knotsU.resize(size_t(m.rows) + 2);
  EXPECT_FALSE(sampling::gpuLimitation(Surface::create(m), Precision::Float));
}

// Weights far from 1 would leave the kernels' range in the homogeneous sums: the GPU path falls
// back with the reason (fp32 beyond [1e-15, 1e15], fp64 beyond [1e-150, 1e150]); the CPU takes them.
TEST(GpuLimits, RationalWeightsFarFromOneAreNamed) {
  CurveModel m = exampleModel<CurveModel>("clamped_bspline.json");
  m.weights.assign(m.points.size(), 1.0);
  EXPECT_FALSE(sampling::gpuLimitation(Curve::create(m), Precision::Float));
  m.weights[2] = 1e20;
  const auto why = sampling::gpuLimitation(Curve::create(m), Precision::Float);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("weights from 1 to 1e+20"), std::string::npos) << *why;
  EXPECT_FALSE(sampling::gpuLimitation(Curve::create(m), Precision::Double));
  m.weights[2] = 1e-200;
  EXPECT_TRUE(sampling::gpuLimitation(Curve::create(m), Precision::Double));
  const CurvePoint p = Curve::create(m).evaluateAt(0.4);  // the CPU path evaluates it
  EXPECT_TRUE(std::isfinite(p.point.x) && std::isfinite(p.d2.y));
}

TEST_F(SamplingGpu, HugeNetInFp32IsScaledExactlyAndBack) {
  sampling::Session session(ctx_);
  SurfaceModel m = exampleModel<SurfaceModel>("surface_aeb.json");
  for (auto& p : m.points) p *= 1e30;  // fp32 kernels would overflow in |du x dv| (1e60)
  const Surface s = Surface::create(m);
  sampling::Report r;
  const DeviceRequest gpu{DeviceKind::Vulkan, Precision::Float, true};
  const DeviceRequest cpu{DeviceKind::Cpu, Precision::Double, false};
  const double scale = bboxDiag(m.points);
  const std::vector<double> point = gathered(session, s, gpu, Field::Point, &r);
  EXPECT_TRUE(r.gpu);
  EXPECT_EQ(r.netScaleExponent, sampling::netScale(m.points, Precision::Float));
  EXPECT_LT(r.netScaleExponent, -90);
  expectNear(gathered(session, s, cpu, Field::Point), point, 4 * kFp32Rel * scale, "point");
  expectNear(gathered(session, s, cpu, Field::Du), gathered(session, s, gpu, Field::Du), 64 * kFp32Rel * scale, "du");
  // Unit normals are scale-free; the net's magnitude must not reach them as inf/NaN.
  expectNear(gathered(session, s, cpu, Field::Normal), gathered(session, s, gpu, Field::Normal), 1e-3, "normal");
  // Lists scale the same way.
  const std::vector<sampling::SurfaceQuery> q = {{false, 0, 0, 0.25, 0.5}, {true, 0, 0, 0.6, 0.3}};
  const auto onGpu = session.evaluate(s, gpu, q), onCpu = session.evaluate(s, cpu, q);
  ASSERT_EQ(onGpu.points.size(), 2u);
  for (size_t i = 0; i < q.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(onGpu.points[i].point[a], onCpu.points[i].point[a], 4 * kFp32Rel * scale) << i;
    }
  }
}

TEST_F(SamplingGpu, KnotVectorBSplinesRunOnTheGpu) {
  sampling::Session session(ctx_);
  const CurveModel cm = exampleModel<CurveModel>("clamped_bspline.json");
  const Curve c = Curve::create(cm);
  const double scale = bboxDiag(cm.points), h = smallestInterval(cm.knots);
  for (Precision p : {Precision::Float, Precision::Double}) {
    const double rel = p == Precision::Float ? kFp32Rel : kFp64Rel;
    const DeviceRequest gpu{DeviceKind::Vulkan, p, true};
    const std::vector<sampling::CurveQuery> q = {{true, 0, 0.0, 0.0}, {true, 0, 0.0, 0.3}, {true, 0, 0.0, 0.5},
                                                 {true, 0, 0.0, 0.99}, {true, 0, 0.0, 1.0}};
    const auto onGpu = session.evaluate(c, gpu, q), onCpu = session.evaluate(c, {DeviceKind::Cpu, p, false}, q);
    EXPECT_TRUE(onGpu.report.gpu);
    for (size_t i = 0; i < q.size(); ++i) {
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(onGpu.points[i].point[a], onCpu.points[i].point[a], 4 * rel * scale) << "u " << q[i].u;
        EXPECT_NEAR(onGpu.points[i].d1[a], onCpu.points[i].d1[a], 4 * rel * scale * 8 * 4 / h) << "u " << q[i].u;
      }
    }
  }
  const SurfaceModel sm = exampleModel<SurfaceModel>("bspline_surface.json");
  const Surface s = Surface::create(sm);
  const double sscale = bboxDiag(sm.points), sh = std::min(smallestInterval(sm.knotsU), smallestInterval(sm.knotsV));
  for (Precision p : {Precision::Float, Precision::Double}) {
    const double rel = p == Precision::Float ? kFp32Rel : kFp64Rel;
    sampling::Report r;
    const std::vector<double> gpuPoints = gathered(session, s, {DeviceKind::Auto, p, true}, Field::Point, &r);
    EXPECT_TRUE(r.gpu);
    expectNear(gathered(session, s, {DeviceKind::Cpu, p, false}, Field::Point), gpuPoints, 4 * rel * sscale, "point");
    expectNear(gathered(session, s, {DeviceKind::Cpu, p, false}, Field::Du),
               gathered(session, s, {DeviceKind::Auto, p, true}, Field::Du), 4 * rel * sscale * 8 * 3 / sh, "du");
  }
}

}  // namespace
}  // namespace shapespline::test
