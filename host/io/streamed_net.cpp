#include <shapespline/io/streamed_net.h>

#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/io/array_stream.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vector>

namespace shapespline::io {

namespace {

// A value rule's first error, kept while the files' finite checks (which the full parse runs
// first, over every file) read on; thrown once they have.
class LaterError {
 public:
  template <class F>
  void check(F&& rule) {
    if (error_) return;
    try {
      rule();
    } catch (const ModelError& e) {
      error_ = e;
    }
  }
  void rethrow() const {
    if (error_) throw *error_;
  }

 private:
  std::optional<ModelError> error_;
};

}  // namespace

StreamedNet streamSurfaceNet(const SurfaceModel& m, const ModelArrays& arrays, SurfaceFingerprint& fingerprint,
                             size_t windowPoints) {
  const DeferredArray* points = deferredArray(arrays, "points");
  if (!points) throw std::logic_error("streamSurfaceNet: the outline's points were read");
  const size_t total = size_t(points->header.count / 3);
  const size_t window = std::max<size_t>(1, std::min(windowPoints, total));
  std::vector<glm::dvec3> net(window);
  StreamedNet out;

  ArrayStream pointFile(*points, arrays.maxValueBytes);
  for (size_t first = 0; first < total; first += window) {
    const size_t n = std::min(window, total - first);
    pointFile.read(&net.data()->x, 3 * n, 3 * std::uint64_t(first));
    out.largestCoordinate = std::max(out.largestCoordinate, largestMagnitude(&net.data()->x, 3 * n));
    fingerprint.points(net.data(), n);
  }

  LaterError alphaRule;
  auto alphaRun = [&](const double* a, size_t n, size_t first) {
    alphaRule.check([&] { checkSurfaceAlphas(a, n, first, m.cols); });
    out.alpha.add(a, n);
    fingerprint.alphas(a, n);
  };
  std::vector<double> values;
  if (const DeferredArray* alpha = deferredArray(arrays, "alpha")) {
    values.resize(window);
    ArrayStream file(*alpha, arrays.maxValueBytes);
    for (size_t first = 0; first < total; first += window) {
      const size_t n = std::min(window, total - first);
      file.read(values.data(), n, first);
      alphaRun(values.data(), n, first);
    }
  } else if (arrays.uniformAlpha) {
    values.assign(window, *arrays.uniformAlpha);
    for (size_t first = 0; first < total; first += window)
      alphaRun(values.data(), std::min(window, total - first), first);
  } else if (!m.alpha.empty()) {
    alphaRun(m.alpha.data(), m.alpha.size(), 0);
  }
  alphaRule.rethrow();

  // Weights (from their file, or written out in the model): the file's finite check over the whole
  // file first, then w > 0 and w P finite, each weight beside its point (the points read again in
  // step; the fingerprint takes the weights after α).
  LaterError weightRule;
  const DeferredArray* weightFile = deferredArray(arrays, "weights");
  if (weightFile || !m.weights.empty()) {
    out.rational = true;
    std::optional<ArrayStream> file;
    if (weightFile) values.resize(window), file.emplace(*weightFile, arrays.maxValueBytes);
    ArrayStream again(*points, arrays.maxValueBytes);
    for (size_t first = 0; first < total; first += window) {
      const size_t n = std::min(window, total - first);
      if (file) file->read(values.data(), n, first);
      const double* w = file ? values.data() : m.weights.data() + first;
      again.read(&net.data()->x, 3 * n, 3 * std::uint64_t(first));
      weightRule.check([&] { checkSurfaceWeights(w, net.data(), n, first, m.cols); });
      fingerprint.weights(w, n);
    }
  }
  weightRule.rethrow();

  if (m.family.construction == Construction::AlphaEB)
    out.verticesShown = alphaEBVerticesSurelyFinite(m, out.largestCoordinate, out.alpha.summary().min);
  return out;
}

}  // namespace shapespline::io
