#pragma once
// An array file of a model outline (io/model_json.h DeferredArray) read again a run at a time, its
// values checked finite and its failures named as the parser names them (ModelError: the key and
// the file). The streams of a net that is never held whole read through it (io/streamed_net.h,
// io/streamed_bands.h).
#include <shapespline/core/model.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/npy_array.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace shapespline::io {

// The outline's deferred array of `key` ("points", "alpha", "weights"), or null when it was read.
inline const DeferredArray* deferredArray(const ModelArrays& arrays, const std::string& key) {
  for (const DeferredArray& a : arrays.deferred)
    if (a.key == key) return &a;
  return nullptr;
}

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
  // Moves on past `count` values unread.
  void skip(std::uint64_t count) {
    guarded([&] { reader_->skip(count); });
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

}  // namespace shapespline::io
