#include <shapespline/io/streamed_net.h>

#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/io/npy_array.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vector>

namespace shapespline::io {

namespace {

const DeferredArray* deferredOf(const ModelArrays& arrays, const std::string& key) {
  for (const DeferredArray& a : arrays.deferred)
    if (a.key == key) return &a;
  return nullptr;
}

// An array file read again, a run at a time; its failures named as the parser names them.
class ArrayStream {
 public:
  ArrayStream(const DeferredArray& array, std::uint64_t maxValueBytes) : array_(array) {
    guarded([&] { reader_.emplace(array.file, maxValueBytes); });
    // The file was replaced since the parse read its header: another array, refused rather than mixed.
    if (reader_->header().shape != array.header.shape || reader_->header().float64 != array.header.float64)
      throw ModelError(array.key, array.name, "the file changed while the model was read");
  }
  // The next `count` values into `out`, checked finite (flat index `first` on).
  void read(double* out, size_t count, std::uint64_t first) {
    guarded([&] { reader_->read(out, count); });
    requireFiniteArrayValues(array_.key, array_.name, array_.header.shape, out, count, first);
  }

 private:
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      throw ModelError(array_.key, array_.name, e.what());
    } catch (const std::runtime_error& e) {
      throw ModelError(array_.key, array_.name, e.what());
    }
  }
  const DeferredArray& array_;
  std::optional<NpyReader> reader_;
};

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
  const DeferredArray* points = deferredOf(arrays, "points");
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
  if (const DeferredArray* alpha = deferredOf(arrays, "alpha")) {
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
  const DeferredArray* weightFile = deferredOf(arrays, "weights");
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
