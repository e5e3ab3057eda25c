// Binary little-endian PLY, welded (the default, io/welded_mesh.h: every grid point once) or per
// item (items x Su x Sv vertices; 2 (Su-1)(Sv-1) triangles or Su-1 edges per item). The header's
// counts follow from the grid alone, so it is written first and the vertices stream; the
// connectivity is regenerated from the grid in finish() without storing any.
// Vertex properties: x y z, nx ny nz (surfaces and --normals), s t (surfaces: uv in [0,1] over the
// model), then <field>_x/_y/_z for every other requested field, in the precision of the samples.
// Shards merge with `shapespline merge` (welded: each shard's owned vertices, the connectivity
// regenerated; per item: vertex blocks concatenated, indices offset).
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/welded_formats.h>

#include <bit>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

namespace shapespline::io {
namespace {

static_assert(std::endian::native == std::endian::little, "the PLY/raw writers assume a little-endian host");

class PlyWriter final : public SampleWriter {
 public:
  explicit PlyWriter(AtomicFile& out) : out_(out) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    if (layout.welded) {
      numbering_ = std::make_unique<WeldedNumbering>(layout.weldGrid(), layout.firstItem,
                                                     layout.firstItem + layout.itemCount);
    }
    const uint64_t vertices = numbering_ ? numbering_->vertexCount() : layout.pointCount();
    if (vertices > std::numeric_limits<uint32_t>::max()) {
      throw std::invalid_argument("PLY stores 32-bit vertex indices: " + std::to_string(vertices) +
                                  " vertices do not fit; use --shard or a raw format");
    }
    const bool dbl = layout.precision == Precision::Double;
    const char* type = dbl ? "double" : "float";
    // Source (escaped: one comment line), the job line `merge` verifies (io/shard_info.h) and, for
    // welded files, the mesh line it renumbers by.
    std::string h = "ply\nformat binary_little_endian 1.0\n" +
                    plyInfoComments(shardInfoOf(layout), escapeText(layout.source));
    if (numbering_) h += std::string(kPlyJobPrefix) + meshInfoLine(meshInfoOf(layout)) + "\n";
    h += metadataComments(layout.metadata, kPlyJobPrefix);  // the same in every shard: merge copies it
    h += "element vertex " + std::to_string(vertices) + "\n";
    fields_.clear();
    for (const char* a : {"x", "y", "z"}) h += std::string("property ") + type + " " + a + "\n";
    fields_.push_back(Field::Point);
    if (layout.fields & fieldBit(Field::Normal)) {
      for (const char* a : {"nx", "ny", "nz"}) h += std::string("property ") + type + " " + a + "\n";
      fields_.push_back(Field::Normal);
    }
    if (layout.surface) h += std::string("property ") + type + " s\nproperty " + type + " t\n";
    for (int f = 0; f < kFieldCount; ++f) {
      const Field field = static_cast<Field>(f);
      if (field == Field::Point || field == Field::Normal || !(layout.fields & fieldBit(field))) continue;
      extra_.push_back(field);
      for (const char* a : {"_x", "_y", "_z"}) {
        h += std::string("property ") + type + " " + std::string(fieldName(field)) + a + "\n";
      }
    }
    const size_t su = static_cast<size_t>(layout.samplesU), sv = static_cast<size_t>(layout.samplesV);
    if (numbering_) {
      h += plyConnectivityHeader(*numbering_);
    } else if (layout.surface) {
      h += "element face " + std::to_string(layout.itemCount * 2 * (su - 1) * (sv - 1)) +
           "\nproperty list uchar uint vertex_indices\n";
    } else {
      h += "element edge " + std::to_string(layout.itemCount * (su - 1)) +
           "\nproperty uint vertex1\nproperty uint vertex2\n";
    }
    h += "end_header\n";
    out_.write(h);
    if (numbering_) {
      stream_ = std::make_unique<WeldedVertexStream>(
          *numbering_, layout.fields, layout.reversed, [this](const WeldedVertex& v) {
            putVertex([&](Field f, int ax) { return v.value(f, ax); }, v.item, v.a, v.b);
          });
    }
  }

  void consume(const GridChunk& chunk) override {
    if (stream_) {
      stream_->consume(chunk);
      return;
    }
    const size_t sv = static_cast<size_t>(layout_.samplesV);
    const size_t n = chunk.pointCount();  // whole items or a row range of one (the faces come in finish())
    for (size_t p = 0; p < n; ++p) {
      const size_t q = chunk.pointInItem(p);
      putVertex([&](Field f, int ax) { return chunk.coord(f, p, ax); }, chunk.itemOf(p), static_cast<int>(q / sv),
                static_cast<int>(q % sv));
    }
  }

  void finish() override {
    if (stream_) {
      stream_->finish();
      writePlyConnectivity(out_, *numbering_, layout_.reversed);
      return;
    }
    const uint32_t su = static_cast<uint32_t>(layout_.samplesU), sv = static_cast<uint32_t>(layout_.samplesV);
    const uint32_t ppi = su * sv;
    for (size_t item = 0; item < layout_.itemCount; ++item) {
      const uint32_t base = static_cast<uint32_t>(item) * ppi;
      if (layout_.surface) {
        for (uint32_t a = 0; a + 1 < su; ++a) {
          for (uint32_t b = 0; b + 1 < sv; ++b) {
            const uint32_t p00 = base + a * sv + b, p10 = p00 + sv, p11 = p10 + 1, p01 = p00 + 1;
            const uint32_t tri[2][3] = {{p00, p10, p11}, {p00, p11, p01}};
            for (const auto& t : tri) {
              char* e = out_.space(13);
              e[0] = 3;
              std::memcpy(e + 1, t, 12);
              out_.advance(13);
            }
          }
        }
      } else {
        for (uint32_t a = 0; a + 1 < su; ++a) {
          const uint32_t edge[2] = {base + a, base + a + 1};
          out_.write(edge, 8);
        }
      }
    }
  }

 private:
  // One vertex record: the header's properties in order; `value(field, axis)`.
  template <class Value>
  void putVertex(const Value& value, uint64_t item, int a, int b) {
    const bool dbl = layout_.precision == Precision::Double;
    char* s = out_.space(512);
    char* e = s;
    auto put = [&](double v) { e = putBinaryValue(e, v, dbl); };
    for (Field f : fields_) {
      for (int ax = 0; ax < 3; ++ax) put(value(f, ax));
    }
    if (layout_.surface) {
      const auto [tu, tv] = layout_.texCoord(item, a, b);
      put(tu);
      put(tv);
    }
    for (Field f : extra_) {
      for (int ax = 0; ax < 3; ++ax) put(value(f, ax));
    }
    out_.advance(static_cast<size_t>(e - s));
  }

  AtomicFile& out_;
  SampleLayout layout_;
  std::vector<Field> fields_, extra_;
  std::unique_ptr<WeldedNumbering> numbering_;  // welded files
  std::unique_ptr<WeldedVertexStream> stream_;
};

}  // namespace

std::unique_ptr<SampleWriter> makePlyWriter(AtomicFile& out) { return std::make_unique<PlyWriter>(out); }

}  // namespace shapespline::io
