#pragma once
// Point clouds of a trimmed face (`sample --trim`, docs/cad.md): of a grid job's samples, only those
// whose knot parameters (U, V) lie inside the model's trim loops (core/trim_classifier.h), each
// written with its (U, V) before the requested fields. The chunks may come from the CPU or the GPU:
// the choice is made on the parameters alone, so both paths keep the same samples. The count is
// known before the first chunk (the classifier runs over the job's parameters in begin()), so
// every header is written up front and memory stays bounded.
//
// Formats: .npy (a structured array: 'uv' (2,), then one (3,) field per requested field), .f32 /
// .f64 (the same records, raw, with the OUT.json sidecar describing them), CSV (U, V, then x y z of
// each field) and PLY (a binary point cloud: x y z of the point, nx ny nz of the normal, u v, then
// the other fields' NAME_x NAME_y NAME_z; no faces). Meshes of trimmed faces are not written.
#include <shapespline/core/model.h>
#include <shapespline/core/trim_classifier.h>
#include <shapespline/io/sample_writer.h>

#include <optional>
#include <vector>

namespace shapespline::io {

bool trimmedPointFormat(OutputFormat format);

class TrimmedPointWriter final : public SampleWriter {
 public:
  // `sidecar`: the OUT.json of .f32/.f64/.npy (may be null for .npy).
  TrimmedPointWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar, const TrimLoops& trim);

  void begin(const SampleLayout& layout) override;
  void consume(const GridChunk& chunk) override;
  void finish() override;

  uint64_t kept() const { return kept_; }  // samples inside the loops (after begin())

 private:
  bool inside(size_t item, size_t pointInItem) const;
  void header();
  void appendRecord(const GridChunk& chunk, size_t p, std::pair<double, double> uv);
  void flush();

  OutputFormat format_;
  AtomicFile& out_;
  AtomicFile* sidecar_;
  TrimClassifier classifier_;
  double tolerance_;
  SampleLayout layout_;
  std::vector<Field> fields_;
  std::vector<std::optional<Field>> columns_;  // a record, in order; nullopt: (U, V)
  bool float64_ = true;
  uint64_t kept_ = 0, written_ = 0;
  std::string buffer_;
};

}  // namespace shapespline::io
