// render::Camera::fit (no GPU): for point clouds seen from many directions, including straight down
// and up, every point projects inside the target rectangle with a depth in (0, 1), the extreme
// projections touch both sides of the target in one axis (to a hundredth of a pixel), and a
// flat set seen face-on is centred in the other. The bounding-sphere frame() is the baseline the
// fill is compared against.
#include <gtest/gtest.h>

#include <shapespline/render/camera.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace shapespline::test {
namespace {

constexpr double kTouchPx = 0.01;  // the camera's matrices are fp32; the fit and projection fp64

struct Extent {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY, zMin = INFINITY, zMax = -INFINITY;
};

Extent project(const render::Camera& cam, const std::vector<glm::dvec3>& pts, int w, int h) {
  Extent e;
  for (const auto& p : pts) {
    const glm::dvec3 px = cam.toPixel(p, w, h);
    e.x0 = std::min(e.x0, px.x);
    e.x1 = std::max(e.x1, px.x);
    e.y0 = std::min(e.y0, px.y);
    e.y1 = std::max(e.y1, px.y);
    e.zMin = std::min(e.zMin, px.z);
    e.zMax = std::max(e.zMax, px.z);
  }
  return e;
}

std::vector<glm::dvec3> cloud(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  const glm::dvec3 scale(1.0 + 9.0 * (d(rng) + 1.0), 1.0 + 2.0 * (d(rng) + 1.0), 0.1 + (d(rng) + 1.0));
  const glm::dvec3 offset(100.0 * d(rng), 100.0 * d(rng), 10.0 * d(rng));
  std::vector<glm::dvec3> pts(static_cast<size_t>(n));
  for (auto& p : pts) p = offset + scale * glm::dvec3(d(rng), d(rng), d(rng));
  return pts;
}

TEST(CameraFit, PointsFillTheTargetTightlyFromEveryDirection) {
  std::mt19937 rng(18);
  struct Image {
    int w, h;
    render::PixelRect target;
  };
  const Image images[] = {{800, 600, {24, 62, 776, 582}}, {300, 400, {5, 5, 295, 395}}, {512, 128, {100, 20, 400, 120}}};
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<glm::dvec3> pts = cloud(rng, 200);
    for (const auto& [az, el] : {std::pair{35.0, 30.0}, {-90.0, 90.0}, {200.0, -90.0}, {10.0, -60.0}, {123.0, 5.0}})
      for (const Image& im : images) {
        SCOPED_TRACE("trial " + std::to_string(trial) + " az " + std::to_string(az) + " el " + std::to_string(el) +
                     " image " + std::to_string(im.w) + "x" + std::to_string(im.h));
        const render::Camera cam = render::Camera::fit(pts, az, el, im.w, im.h, im.target);
        const Extent e = project(cam, pts, im.w, im.h);
        const double tol = kTouchPx;
        EXPECT_GE(e.x0, im.target.x0 - tol);
        EXPECT_LE(e.x1, im.target.x1 + tol);
        EXPECT_GE(e.y0, im.target.y0 - tol);
        EXPECT_LE(e.y1, im.target.y1 + tol);
        EXPECT_GT(e.zMin, 0.0);
        EXPECT_LT(e.zMax, 1.0);
        const bool tightX = std::abs(e.x0 - im.target.x0) < tol && std::abs(e.x1 - im.target.x1) < tol;
        const bool tightY = std::abs(e.y0 - im.target.y0) < tol && std::abs(e.y1 - im.target.y1) < tol;
        EXPECT_TRUE(tightX || tightY) << "x " << e.x0 << ".." << e.x1 << " y " << e.y0 << ".." << e.y1;
      }
  }
}

TEST(CameraFit, FlatSetSeenFaceOnIsCentredInTheLooseAxis) {
  // A 2-D curve from above: one depth, so the loose axis is exactly centred.
  std::vector<glm::dvec3> pts;
  for (int k = 0; k <= 100; ++k) pts.push_back({3.0 + 4.0 * std::cos(0.0628 * k), -1.0 + std::sin(0.0628 * k), 0.0});
  const render::PixelRect target{10, 40, 790, 590};
  const render::Camera cam = render::Camera::fit(pts, -90.0, 90.0, 800, 600, target);
  const Extent e = project(cam, pts, 800, 600);
  EXPECT_NEAR(e.x0, target.x0, 1e-3);
  EXPECT_NEAR(e.x1, target.x1, 1e-3);
  EXPECT_NEAR(e.y0 - target.y0, target.y1 - e.y1, 1e-3) << "y " << e.y0 << ".." << e.y1;
}

TEST(CameraFit, FillsMoreThanTheBoundingSphere) {
  // A bumpy 4 x 5 sheet as render_test draws it, at the CLI's default view.
  std::vector<glm::dvec3> pts;
  for (int i = 0; i <= 30; ++i)
    for (int j = 0; j <= 40; ++j) {
      const double x = 0.1 * i, y = 0.1 * j;
      pts.push_back({x, y, 0.6 * std::sin(1.3 * x) * std::cos(0.9 * y) + 0.1 * x * y});
    }
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const int w = 800, h = 600;
  const Extent sphere = project(render::Camera::frame(lo, hi, 35.0, 30.0, double(w) / h), pts, w, h);
  const Extent fitted = project(render::Camera::fit(pts, 35.0, 30.0, w, h, {0, 0, double(w), double(h)}), pts, w, h);
  const auto fill = [&](const Extent& e) { return std::max((e.x1 - e.x0) / w, (e.y1 - e.y0) / h); };
  const auto area = [&](const Extent& e) { return (e.x1 - e.x0) * (e.y1 - e.y0) / (double(w) * h); };
  std::printf("bounding sphere: fill %.3f, box area %.3f; fit: fill %.3f, box area %.3f\n", fill(sphere), area(sphere),
              fill(fitted), area(fitted));
  EXPECT_NEAR(fill(fitted), 1.0, 1e-5);
  EXPECT_LT(fill(sphere), 0.9 * fill(fitted));
}

TEST(CameraFit, OnePointGetsAFiniteCamera) {
  const std::vector<glm::dvec3> pts{{1.0, 2.0, 3.0}};
  const render::Camera cam = render::Camera::fit(pts, 35.0, 30.0, 100, 100, {10, 10, 90, 90});
  const glm::dvec3 px = cam.toPixel(pts[0], 100, 100);
  EXPECT_TRUE(std::isfinite(px.x) && std::isfinite(px.y) && std::isfinite(px.z));
  EXPECT_NEAR(px.x, 50.0, 0.5);  // the eye sits close to it: fp32 rounding moves it a little
  EXPECT_NEAR(px.y, 50.0, 0.5);
}

}  // namespace
}  // namespace shapespline::test
