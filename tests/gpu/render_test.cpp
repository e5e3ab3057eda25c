// The headless render path (render/renderer.h + gpu/tessellator.h): a known α-EB surface is
// tessellated inside the frame's command buffer and drawn; the image's coverage mask must match a
// CPU rasterisation of the CPU-evaluated surface projected with the same camera (IoU >= 99%), the
// shading must vary, no vertex may be NaN, and the validation layers must stay silent for the whole
// path (the VulkanTest fixture fails the test otherwise). Set SHAPESPLINE_RENDER_TEST_OUT=dir to
// keep the images.
#include <gtest/gtest.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>

#include <shapespline/core/surface.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/io/png_writer.h>
#include <shapespline/render/renderer.h>
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

constexpr int kSize = 256;
constexpr double kMinOverlap = 0.99;

SurfaceModel knownSurface() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 4;
  m.family.lambda = 0.0;
  m.rows = 4;
  m.cols = 5;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j)
      m.points.push_back({double(i), double(j), 0.6 * std::sin(1.3 * i) * std::cos(0.9 * j) + 0.1 * i * j});
  m.alpha.assign(size_t(m.rows) * m.cols, 0.7);
  m.alpha[size_t(1) * m.cols + 2] = 1.0;
  return m;
}

void box(const std::vector<glm::dvec3>& pts, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  for (const auto& p : pts) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
}

// Pixel-centre coverage of projected triangles.
std::vector<char> rasterise(const std::vector<glm::dvec3>& px, const std::vector<uint32_t>& tris, int w, int h) {
  std::vector<char> mask(size_t(w) * h, 0);
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    const glm::dvec3 &a = px[tris[t]], &b = px[tris[t + 1]], &c = px[tris[t + 2]];
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(w - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(h - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px_ = x + 0.5, py = y + 0.5;
        const double w0 = ((b.x - px_) * (c.y - py) - (b.y - py) * (c.x - px_)) / area;
        const double w1 = ((c.x - px_) * (a.y - py) - (c.y - py) * (a.x - px_)) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 >= 0 && w1 >= 0 && w2 >= 0) mask[size_t(y) * w + x] = 1;
      }
  }
  return mask;
}

void keep(const render::Image& img, const char* name) {
  const char* dir = std::getenv("SHAPESPLINE_RENDER_TEST_OUT");
  if (!dir) return;
  io::writePng(std::filesystem::path(dir) / name, img.width, img.height, img.rgba);
}

class RenderTest : public VulkanTest {};

TEST_F(RenderTest, SurfaceSilhouetteMatchesCpuProjectionAndShadingVaries) {
  const SurfaceModel model = knownSurface();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 12));
  const TessTopology& topo = tess.topology();

  // CPU: the same samples evaluated in fp64.
  std::vector<glm::dvec3> cpuPts(topo.vertexCount);
  const PatchRange r = cpu.patches();
  for (uint32_t k = 0; k < topo.vertexCount; ++k) {
    const TessSample& s = topo.samples[k];
    cpuPts[k] = cpu.evaluate(s.a + r.u.first, s.b + r.v.first, s.u, s.v).point;
  }
  glm::dvec3 lo, hi;
  box(cpuPts, lo, hi);
  const render::Camera cam = render::Camera::frame(lo, hi, 35.0, 30.0, 1.0);

  render::OffscreenRenderer renderer(ctx_, kSize, kSize);
  render::Scene scene;
  scene.prepare = [&](VkCommandBuffer cmd) { tess.record(cmd); };
  scene.meshes.push_back({tess.vertexBuffer().handle(), tess.indexBuffer().handle(), tess.indexCount()});
  const render::Image img = renderer.render(scene, cam);
  keep(img, "render_test_surface.png");

  // No NaN in the vertices the frame drew.
  std::vector<gpu::tess_layout::TessVertex> v(tess.vertexCount());
  tess.vertexBuffer().downloadSpan(std::span<gpu::tess_layout::TessVertex>(v));
  for (uint32_t k = 0; k < v.size(); ++k)
    for (float f : {v[k].position[0], v[k].position[1], v[k].position[2], v[k].normal[0], v[k].normal[1],
                    v[k].normal[2], v[k].uv[0], v[k].uv[1]})
      ASSERT_TRUE(std::isfinite(f)) << "vertex " << k;

  // Silhouette: coverage mask (alpha) against the CPU projection.
  std::vector<glm::dvec3> px(cpuPts.size());
  for (size_t k = 0; k < px.size(); ++k) px[k] = cam.toPixel(cpuPts[k], kSize, kSize);
  const std::vector<char> expected = rasterise(px, topo.indices, kSize, kSize);
  size_t inter = 0, uni = 0, covered = 0;
  std::set<uint32_t> colours;
  double sum = 0.0, sum2 = 0.0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const uint8_t* p = img.pixel(x, y);
      const bool got = p[3] == 255;
      const bool want = expected[size_t(y) * kSize + x] != 0;
      inter += got && want;
      uni += got || want;
      if (!got) continue;
      ++covered;
      colours.insert(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
      const double lum = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
      sum += lum;
      sum2 += lum * lum;
    }
  ASSERT_GT(uni, size_t(kSize * kSize / 10)) << "the surface covers too little of the image to test";
  const double overlap = double(inter) / double(uni);
  std::printf("silhouette overlap (IoU) %.4f: %zu of %zu pixels\n", overlap, inter, uni);
  EXPECT_GE(overlap, kMinOverlap) << inter << " of " << uni << " pixels agree";
  const double mean = sum / double(covered);
  const double stddev = std::sqrt(std::max(0.0, sum2 / double(covered) - mean * mean));
  EXPECT_GT(colours.size(), 50u) << "shading looks constant";
  EXPECT_GT(stddev, 5.0) << "luminance barely varies over the surface";
  // The background keeps its colour and zero coverage.
  EXPECT_EQ(img.pixel(0, 0)[3], 0);
}

TEST_F(RenderTest, WireframeAndOverlaysDrawOverTheSurface) {
  const SurfaceModel model = knownSurface();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 6));
  const std::vector<uint32_t> edges = triangleEdges(tess.topology().indices);
  vk::Buffer wire = vk::Buffer::create(ctx(), edges.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       vk::MemoryUse::DeviceLocal, "test.wire");
  wire.uploadSpan(std::span<const uint32_t>(edges));
  glm::dvec3 lo, hi;
  box(model.points, lo, hi);
  render::OffscreenRenderer renderer(ctx_, kSize, kSize);
  render::Scene scene;
  scene.prepare = [&](VkCommandBuffer cmd) { tess.record(cmd); };
  render::MeshDraw mesh{tess.vertexBuffer().handle(), tess.indexBuffer().handle(), tess.indexCount(), wire.handle(),
                        uint32_t(edges.size())};
  scene.meshes.push_back(mesh);
  for (const auto& p : model.points) render::addMarker(scene.markers, p, 6.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  const render::Image img = renderer.render(scene, render::Camera::frame(lo, hi, 35.0, 30.0, 1.0));
  keep(img, "render_test_wireframe.png");
  size_t red = 0, dark = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const uint8_t* p = img.pixel(x, y);
      red += p[0] == 255 && p[1] == 0 && p[2] == 0;
      dark += p[0] < 40 && p[1] < 40 && p[2] < 50 && p[3] == 255;
    }
  EXPECT_GT(red, size_t(model.points.size()) * 10) << "data point markers missing";
  EXPECT_GT(dark, 500u) << "wireframe lines missing";
}

// MeshDraw::indirectBuffer: the same mesh drawn from a VkDrawIndexedIndirectCommand gives the same
// image as the direct draw; a command with indexCount 0 draws nothing.
TEST_F(RenderTest, IndirectDrawMatchesDirectDraw) {
  const Surface cpu = Surface::create(knownSurface());
  gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 8));
  glm::dvec3 lo, hi;
  box(knownSurface().points, lo, hi);
  const render::Camera cam = render::Camera::frame(lo, hi, 35.0, 30.0, 1.0);
  render::OffscreenRenderer renderer(ctx_, kSize, kSize);
  auto drawWith = [&](VkBuffer indirect) {
    render::Scene scene;
    scene.prepare = [&](VkCommandBuffer cmd) { tess.record(cmd); };
    render::MeshDraw mesh{tess.vertexBuffer().handle(), tess.indexBuffer().handle(), tess.indexCount()};
    if (indirect != VK_NULL_HANDLE) {
      mesh.indexCount = 0;  // ignored for an indirect draw
      mesh.indirectBuffer = indirect;
    }
    scene.meshes.push_back(mesh);
    return renderer.render(scene, cam);
  };
  auto commandBuffer = [&](uint32_t indexCount) {
    const VkDrawIndexedIndirectCommand command{indexCount, 1, 0, 0, 0};
    vk::Buffer b = vk::Buffer::create(ctx(), sizeof(command), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      vk::MemoryUse::DeviceLocal, "test.indirect");
    b.uploadSpan(std::span<const VkDrawIndexedIndirectCommand>(&command, 1));
    return b;
  };
  const render::Image direct = drawWith(VK_NULL_HANDLE);
  const vk::Buffer full = commandBuffer(tess.indexCount());
  const render::Image indirect = drawWith(full.handle());
  size_t covered = 0;
  for (size_t k = 3; k < direct.rgba.size(); k += 4) covered += direct.rgba[k] == 255;
  ASSERT_GT(covered, size_t(kSize * kSize / 10)) << "the direct draw covers too little to compare";
  EXPECT_TRUE(direct.rgba == indirect.rgba) << "the indirect draw differs from the direct draw";
  const vk::Buffer none = commandBuffer(0);
  const render::Image empty = drawWith(none.handle());
  for (size_t k = 3; k < empty.rgba.size(); k += 4) ASSERT_EQ(empty.rgba[k], 0) << "pixel " << k / 4 << " drawn";
}

}  // namespace
}  // namespace shapespline::test
