#include <shapespline/viewer/subject.h>

#include <algorithm>
#include <cmath>

namespace shapespline::viewer {

// proj[1][1] is ±1 / tan(fovY / 2) (Vulkan's y down flips the sign): the image's height spans
// 2 depth / |proj[1][1]| at that depth.
double View::pixelSize(double depth) const {
  const double focal = std::abs(double(camera.proj[1][1]));
  return 2.0 * depth / (focal * std::max(1u, extent.height));
}

}  // namespace shapespline::viewer
