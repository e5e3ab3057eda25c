// Wavefront OBJ, welded (the default) or per item.
// Welded (io/welded_mesh.h): every grid point once as v, vt, vn lines (curves: v), in the welded
// order, then the triangles (`f i/i/i ...`, v/vt/vn share one index) or the curve's one `l`
// polyline, with 1-based absolute indices; a shard is a mesh of its own items (its foreign
// vertices last) and `merge` renumbers the shards into the unsharded file.
// Per item: per patch its Su x Sv vertices followed by two triangles per grid cell; curves: the
// vertices of a span followed by one `l` polyline. Unsharded files use absolute indices for the
// widest reader support; a shard uses relative (negative) indices, which the OBJ specification
// allows, so that `cat shard1.obj shard2.obj ... > whole.obj` is the merged mesh.
// Numbers in the shortest form that reads back to the value as --precision stores it
// (io/number_text.h writeValue).
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/welded_formats.h>

#include <cstring>
#include <memory>
#include <string>

namespace shapespline::io {
namespace {

class ObjWriter final : public SampleWriter {
 public:
  explicit ObjWriter(AtomicFile& out) : out_(out) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    relative_ = layout.sharded() && !layout.welded;
    // Source, item range and the job line `merge` verifies (io/shard_info.h); the path escaped so
    // that it stays one comment line. Welded files add the mesh line `merge` renumbers by.
    std::string h = objHeader(shardInfoOf(layout), escapeText(layout.source), layout.welded);
    if (layout.welded) {
      h += std::string(kObjJobPrefix) + meshInfoLine(meshInfoOf(layout)) + "\n";
    }
    h += metadataComments(layout.metadata, kObjJobPrefix);  // the same in every shard: merge copies it
    if (layout.welded) {
      numbering_ = std::make_unique<WeldedNumbering>(layout.weldGrid(), layout.firstItem,
                                                     layout.firstItem + layout.itemCount);
      stream_ = std::make_unique<WeldedVertexStream>(*numbering_, layout.fields, layout.reversed,
                                                     [this](const WeldedVertex& v) { writeVertex(v); });
    }
    out_.write(h);
  }

  void consume(const GridChunk& chunk) override {
    if (stream_) {
      stream_->consume(chunk);
    } else {
      consumeItems(chunk);
    }
  }

  void finish() override {
    if (!stream_) return;
    stream_->finish();
    writeObjConnectivity(out_, *numbering_, layout_.reversed);
  }

 private:
  void writeVertex(const WeldedVertex& v) {
    char* s = out_.space(256);
    char* e = s;
    *e++ = 'v';
    for (int ax = 0; ax < 3; ++ax) {
      *e++ = ' ';
      e = writeValue(e, v.value(Field::Point, ax), layout_.precision);
    }
    *e++ = '\n';
    if (layout_.surface) {
      const auto [tu, tv] = layout_.texCoord(v.item, v.a, v.b);
      e = writeTexCoord(e, tu, tv);
      *e++ = 'v';
      *e++ = 'n';
      for (int ax = 0; ax < 3; ++ax) {
        *e++ = ' ';
        e = writeValue(e, v.value(Field::Normal, ax), layout_.precision);
      }
      *e++ = '\n';
    }
    out_.advance(static_cast<size_t>(e - s));
  }
  char* writeTexCoord(char* e, double tu, double tv) const {
    *e++ = 'v';
    *e++ = 't';
    *e++ = ' ';
    e = writeValue(e, tu, layout_.precision);
    *e++ = ' ';
    e = writeValue(e, tv, layout_.precision);
    *e++ = '\n';
    return e;
  }

  // Per item. A patch larger than a chunk arrives as row ranges: its vertices stream chunk by chunk
  // and its faces (index arithmetic only) follow its last vertex, so the bytes do not depend on the
  // chunking.
  void consumeItems(const GridChunk& chunk) {
    const size_t ppi = chunk.pointsPerItem, sv = static_cast<size_t>(layout_.samplesV);
    const size_t n = chunk.pointCount();
    for (size_t p = 0; p < n; ++p) {
      const size_t item = chunk.itemOf(p), q = chunk.pointInItem(p);
      char* s = out_.space(256);
      char* e = s;
      *e++ = 'v';
      for (int ax = 0; ax < 3; ++ax) {
        *e++ = ' ';
        e = writeValue(e, chunk.coord(Field::Point, p, ax), layout_.precision);
      }
      *e++ = '\n';
      if (layout_.surface) {
        const auto [tu, tv] = layout_.texCoord(item, static_cast<int>(q / sv), static_cast<int>(q % sv));
        e = writeTexCoord(e, tu, tv);
        *e++ = 'v';
        *e++ = 'n';
        for (int ax = 0; ax < 3; ++ax) {
          *e++ = ' ';
          e = writeValue(e, chunk.coord(Field::Normal, p, ax), layout_.precision);
        }
        *e++ = '\n';
      }
      out_.advance(static_cast<size_t>(e - s));
      if (q + 1 == ppi) {
        if (layout_.surface) writeFaces(); else writePolyline();
        vertices_ += ppi;
      }
    }
  }

  // Index of vertex `local` of the item just written.
  long long index(size_t local) const {
    const long long ppi = static_cast<long long>(layout_.pointsPerItem());
    return relative_ ? static_cast<long long>(local) - ppi : static_cast<long long>(vertices_ + local + 1);
  }
  char* ref(char* e, size_t local, bool triple) {
    const long long i = index(local);
    char* start = e;
    e = writeInteger(e, i);
    if (triple) {
      const size_t n = static_cast<size_t>(e - start);
      *e++ = '/';
      std::memcpy(e, start, n);
      e += n;
      *e++ = '/';
      std::memcpy(e, start, n);
      e += n;
    }
    return e;
  }
  void writeFaces() {
    const int su = layout_.samplesU, sv = layout_.samplesV;
    for (int a = 0; a + 1 < su; ++a) {
      for (int b = 0; b + 1 < sv; ++b) {
        const size_t p00 = static_cast<size_t>(a) * sv + b, p10 = p00 + sv, p11 = p10 + 1, p01 = p00 + 1;
        // (p00, p10, p11) and (p00, p11, p01): counter-clockwise seen from du x dv.
        const size_t tri[2][3] = {{p00, p10, p11}, {p00, p11, p01}};
        for (const auto& t : tri) {
          char* s = out_.space(256);
          char* e = s;
          *e++ = 'f';
          for (size_t k : t) {
            *e++ = ' ';
            e = ref(e, k, true);
          }
          *e++ = '\n';
          out_.advance(static_cast<size_t>(e - s));
        }
      }
    }
  }
  void writePolyline() {
    out_.write("l", 1);
    for (size_t k = 0; k < layout_.pointsPerItem(); ++k) {
      char* s = out_.space(64);
      char* e = s;
      *e++ = ' ';
      e = ref(e, k, false);
      out_.advance(static_cast<size_t>(e - s));
    }
    out_.write("\n", 1);
  }

  AtomicFile& out_;
  SampleLayout layout_;
  bool relative_ = false;
  size_t vertices_ = 0;
  std::unique_ptr<WeldedNumbering> numbering_;  // welded files
  std::unique_ptr<WeldedVertexStream> stream_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeObjWriter(AtomicFile& out) { return std::make_unique<ObjWriter>(out); }

}  // namespace shapespline::io
