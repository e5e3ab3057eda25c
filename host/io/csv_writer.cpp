// CSV with one header line. Curves: span,t,u,<fields>; surfaces: patch_i,patch_j,u,v,U,V,<fields>
// (u,v local, U,V global). Each field is written as <name>_x,<name>_y[,<name>_z] (2-D curves have
// no z column). Every number (parameters too) in the shortest form that reads back to the value as
// --precision stores it: fp32 (at most 9 significant digits) or fp64 (at most 17); io/number_text.h.
#include <shapespline/io/number_text.h>
#include <shapespline/io/sample_writer.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace shapespline::io {
namespace {

class CsvWriter final : public SampleWriter {
 public:
  explicit CsvWriter(AtomicFile& out) : out_(out) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    dim_ = layout.surface ? 3 : layout.dimension;
    // Parameters are printed in the file's precision too: an fp32 file cannot hold one beyond 3.4e38.
    if (layout.precision == Precision::Float) {
      const size_t rows = layout.rowCount();
      for (size_t k = 0; k < rows + layout.paramV.size(); ++k) {
        const auto [a, b] = k < rows ? layout.rowParameter(k) : layout.paramV[k - rows];
        for (double x : {a, b}) {
          if (std::abs(x) > static_cast<double>(std::numeric_limits<float>::max())) {
            char buf[kMaxNumberChars];
            throw DerivedValueError("global parameter " + std::string(buf, writeNumber(buf, x)) +
                                    " exceeds the fp32 range of the output (use --precision double); "
                                    "nothing was written");
          }
        }
      }
    }
    std::string h = layout.surface ? "patch_i,patch_j,u,v,U,V" : "span,t,u";
    for (int f = 0; f < kFieldCount; ++f) {
      const Field field = static_cast<Field>(f);
      if (!(layout.fields & fieldBit(field))) continue;
      fields_.push_back(field);
      const char* axes[3] = {"_x", "_y", "_z"};
      // Appended piece by piece (a GCC 12 -Wstringop-overflow false positive on "," + string&&).
      for (int a = 0; a < dim_; ++a) {
        h += ',';
        if (field == Field::Point) {
          h += "xyz"[a];
        } else {
          h += fieldName(field);
          h += axes[a];
        }
      }
    }
    h += "\n";
    out_.write(h);
  }

  void setIdentity(const std::string& job, const JobMetadata& metadata) override {
    layout_.job = job;
    layout_.metadata = metadata;
  }
  void consume(const GridChunk& chunk) override {
    const int sv = layout_.samplesV, su = layout_.samplesU;
    const size_t n = chunk.pointCount();  // whole items or a row range of one
    for (size_t p = 0; p < n; ++p) {
      const size_t item = chunk.itemOf(p), q = chunk.pointInItem(p);
      const auto [iu, iv] = layout_.itemIndex(item);
      const int a = static_cast<int>(q / static_cast<size_t>(sv)), b = static_cast<int>(q % static_cast<size_t>(sv));
      char* s = out_.space(64 + fields_.size() * 3 * 26);
      char* e = s;
      const auto [gu, gv] = layout_.parameter(item, a, b);
      const double lu = su > 1 ? static_cast<double>(a) / (su - 1) : 0.0;
      e = writeInteger(e, static_cast<long long>(iu));
      *e++ = ',';
      if (layout_.surface) {
        const double lv = sv > 1 ? static_cast<double>(b) / (sv - 1) : 0.0;
        e = writeInteger(e, static_cast<long long>(iv));
        *e++ = ',';
        e = writeValue(e, lu, layout_.precision);
        *e++ = ',';
        e = writeValue(e, lv, layout_.precision);
        *e++ = ',';
        e = writeValue(e, gu, layout_.precision);
        *e++ = ',';
        e = writeValue(e, gv, layout_.precision);
      } else {
        e = writeValue(e, lu, layout_.precision);
        *e++ = ',';
        e = writeValue(e, gu, layout_.precision);
      }
      for (Field f : fields_) {
        for (int ax = 0; ax < dim_; ++ax) {
          *e++ = ',';
          e = writeValue(e, chunk.coord(f, p, ax), layout_.precision);
        }
      }
      *e++ = '\n';
      out_.advance(static_cast<size_t>(e - s));
    }
  }

  void finish() override {}

 private:
  AtomicFile& out_;
  SampleLayout layout_;
  int dim_ = 3;
  std::vector<Field> fields_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeCsvWriter(AtomicFile& out) { return std::make_unique<CsvWriter>(out); }

}  // namespace shapespline::io
