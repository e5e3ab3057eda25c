// glTF 2.0 (.glb, or .gltf + its .bin), serialized by Debian's tinygltf (libtinygltf-dev).
//
// One scene, one node, one mesh with one primitive, one buffer. The mesh is welded
// (io/welded_mesh.h): every distinct grid point once, in the numbering's order. Surfaces:
// TRIANGLES, counter-clockwise seen from the front (the side the stored normals point to), with
// POSITION, NORMAL and TEXCOORD_0; curves: LINE_STRIP, or LINE_LOOP for a closed curve (the loop
// closes itself, so its first vertex is not repeated), with POSITION only. Indices UNSIGNED_SHORT
// when every index fits below 65535 (the primitive-restart value is never used), else UNSIGNED_INT.
//
// Positions are re-centred: the node's translation is the centre of the points' bounding box (in
// fp64) and POSITION holds float(p - centre), so fp32 keeps its digits for a model far from the
// origin; the POSITION min/max are those of the stored floats (the validator compares them exactly).
// Texture coordinates: s = normalised global U, t = 1 - normalised global V (SampleLayout::texCoord
// gives both in [0, 1] with V upwards; glTF's t points down), so an image lies on the surface as it
// does with the OBJ/PLY texture coordinates. The model's coordinates are written as they are (no
// change to glTF's +Y up). Job metadata (io/job_metadata.h) goes into the mesh's `extras`,
// "shapespline <version>" into asset.generator.
//
// tinygltf holds the whole model in memory, so the caller caps the vertex count (kMaxGltfVertices).
// .glb: tinygltf writes the whole file (JSON and BIN chunk) through a stream buffer into the
// AtomicFile. .gltf: tinygltf's stream writer would embed the buffer as base64, so it serializes the
// JSON with an empty buffer and the writer then sets that buffer's "uri" (the .bin's file name,
// percent-encoded) and "byteLength"; the bytes go to the .bin through the second AtomicFile of the
// same OutputSet, so the .gltf and its .bin appear together or not at all.
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/welded_mesh.h>
#include <shapespline/version.h>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>

namespace shapespline::io {

std::filesystem::path gltfBufferPath(const std::filesystem::path& gltf) {
  std::filesystem::path p = gltf;
  return p.replace_extension(".bin");
}

namespace {

constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;

// An ostream's bytes into an AtomicFile; a write failure is kept and rethrown by the caller (an
// ostream would turn it into a bad bit).
class AtomicFileBuf final : public std::streambuf {
 public:
  explicit AtomicFileBuf(AtomicFile& out) : out_(out) {}
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (error_) return 0;
    try {
      out_.write(s, static_cast<size_t>(n));
    } catch (...) {
      error_ = std::current_exception();
      return 0;
    }
    return n;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  AtomicFile& out_;
  std::exception_ptr error_;
};

// JSON (io/job_metadata.h) as a tinygltf::Value; integers beyond int32 become reals (tinygltf's
// integers are int).
tinygltf::Value toValue(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::boolean: return tinygltf::Value(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: {
      if (j.is_number_unsigned() ? j.get<uint64_t>() <= static_cast<uint64_t>(std::numeric_limits<int>::max())
                                 : (j.get<int64_t>() >= std::numeric_limits<int>::min() &&
                                    j.get<int64_t>() <= std::numeric_limits<int>::max()))
        return tinygltf::Value(static_cast<int>(j.get<int64_t>()));
      return tinygltf::Value(j.get<double>());
    }
    case nlohmann::json::value_t::number_float: return tinygltf::Value(j.get<double>());
    case nlohmann::json::value_t::string: return tinygltf::Value(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      tinygltf::Value::Array a;
      a.reserve(j.size());
      for (const auto& e : j) a.push_back(toValue(e));
      return tinygltf::Value(std::move(a));
    }
    case nlohmann::json::value_t::object: {
      tinygltf::Value::Object o;
      for (const auto& [k, v] : j.items()) o.emplace(k, toValue(v));
      return tinygltf::Value(std::move(o));
    }
    default: return tinygltf::Value();
  }
}

// RFC 3986: every byte but the unreserved ones percent-encoded (a file name as a relative URI).
std::string uriOf(const std::string& name) {
  static const char* hex = "0123456789ABCDEF";
  std::string s;
  for (unsigned char c : name) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      s += static_cast<char>(c);
    } else {
      s += '%';
      s += hex[c >> 4];
      s += hex[c & 15];
    }
  }
  return s;
}

class GltfWriter final : public SampleWriter {
 public:
  // `bin` null: .glb (one file); else .gltf with its buffer in `bin`.
  GltfWriter(AtomicFile& out, AtomicFile* bin) : out_(out), bin_(bin) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    if (layout.sharded()) throw std::logic_error("glTF output is never sharded");
    if (layout.surface && !(layout.fields & fieldBit(Field::Normal))) throw std::logic_error("glTF surfaces need normals");
    numbering_.emplace(layout_.weldGrid(), layout_.firstItem, layout_.firstItem + layout_.itemCount);
    vertices_ = numbering_->vertexCount();
    if (vertices_ > kMaxGltfVertices) throw std::logic_error("glTF vertex count beyond kMaxGltfVertices");
    positions_.reserve(static_cast<size_t>(vertices_) * 3);
    if (layout_.surface) {
      normals_.reserve(static_cast<size_t>(vertices_) * 3);
      texCoords_.reserve(static_cast<size_t>(vertices_) * 2);
    }
    stream_.emplace(*numbering_, layout_.fields, layout_.reversed, [this](const WeldedVertex& v) { add(v); });
  }

  void consume(const GridChunk& chunk) override { stream_->consume(chunk); }

  void finish() override {
    stream_->finish();
    if (positions_.size() != vertices_ * 3) throw std::logic_error("welded vertex stream: wrong vertex count");
    tinygltf::Model model = buildModel();
    if (bin_) {
      writeGltf(model);
    } else {
      AtomicFileBuf buf(out_);
      std::ostream os(&buf);
      tinygltf::TinyGLTF gltf;
      const bool ok = gltf.WriteGltfSceneToStream(&model, os, false, true);
      os.flush();
      buf.rethrow();
      if (!ok || !os) throw OutputWriteError(out_.option(), out_.target().string(), "tinygltf could not write the .glb");
    }
  }

 private:
  void add(const WeldedVertex& v) {
    for (int ax = 0; ax < 3; ++ax) positions_.push_back(v.value(Field::Point, ax));
    if (layout_.surface) {
      for (int ax = 0; ax < 3; ++ax) normals_.push_back(static_cast<float>(v.value(Field::Normal, ax)));
      const auto [s, t] = layout_.texCoord(v.item, v.a, v.b);
      texCoords_.push_back(static_cast<float>(s));
      texCoords_.push_back(static_cast<float>(1.0 - t));
    }
  }

  std::vector<uint32_t> indices(int* mode) const {
    std::vector<uint32_t> idx;
    if (layout_.surface) {
      *mode = TINYGLTF_MODE_TRIANGLES;
      idx.reserve(static_cast<size_t>(numbering_->triangleCount()) * 3);
      numbering_->forEachTriangle(layout_.reversed, [&](uint64_t a, uint64_t b, uint64_t c) {
        idx.push_back(static_cast<uint32_t>(a));
        idx.push_back(static_cast<uint32_t>(b));
        idx.push_back(static_cast<uint32_t>(c));
      });
    } else {
      idx.reserve(static_cast<size_t>(numbering_->polylineLength()));
      numbering_->forEachPolylinePoint([&](uint64_t i) { idx.push_back(static_cast<uint32_t>(i)); });
      // A closed curve sampled whole ends with its first point again: a LINE_LOOP closes itself.
      const bool loop = layout_.closed && numbering_->whole() && idx.size() > 2 && idx.back() == idx.front();
      if (loop) idx.pop_back();
      *mode = loop ? TINYGLTF_MODE_LINE_LOOP : TINYGLTF_MODE_LINE_STRIP;
    }
    return idx;
  }

  // Appends `bytes` to the buffer at a 4-byte aligned offset as a new buffer view.
  static int addView(tinygltf::Model& m, const void* data, size_t bytes, int target) {
    auto& buf = m.buffers[0].data;
    buf.resize((buf.size() + 3) / 4 * 4, 0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buf.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
    m.bufferViews.push_back(view);
    return static_cast<int>(m.bufferViews.size()) - 1;
  }

  static int addAccessor(tinygltf::Model& m, int view, int componentType, int type, size_t count,
                         std::vector<double> min = {}, std::vector<double> max = {}) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    a.minValues = std::move(min);
    a.maxValues = std::move(max);
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size()) - 1;
  }

  // Per-component min/max of `values` (k per vertex).
  static void bounds(const std::vector<float>& values, int k, std::vector<double>& min, std::vector<double>& max) {
    min.assign(static_cast<size_t>(k), std::numeric_limits<double>::infinity());
    max.assign(static_cast<size_t>(k), -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < values.size(); ++i) {
      const size_t c = i % static_cast<size_t>(k);
      min[c] = std::min(min[c], static_cast<double>(values[i]));
      max[c] = std::max(max[c], static_cast<double>(values[i]));
    }
  }

  tinygltf::Model buildModel() {
    tinygltf::Model m;
    m.asset.version = "2.0";
    m.asset.generator = std::string("shapespline ") + SHAPESPLINE_VERSION_STRING;
    m.buffers.emplace_back();
    {
      const size_t v = static_cast<size_t>(vertices_);
      const size_t indexCount = layout_.surface ? static_cast<size_t>(numbering_->triangleCount()) * 3
                                                : static_cast<size_t>(numbering_->polylineLength());
      m.buffers[0].data.reserve(v * (layout_.surface ? 32 : 12) + indexCount * 4 + 16);
    }

    // Re-centre on the bounding box's centre, in fp64; store the differences as fp32.
    double lo[3], hi[3], centre[3];
    for (int ax = 0; ax < 3; ++ax) {
      lo[ax] = std::numeric_limits<double>::infinity();
      hi[ax] = -std::numeric_limits<double>::infinity();
    }
    for (size_t i = 0; i < positions_.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], positions_[i]);
      hi[i % 3] = std::max(hi[i % 3], positions_[i]);
    }
    for (int ax = 0; ax < 3; ++ax) centre[ax] = vertices_ ? lo[ax] + (hi[ax] - lo[ax]) / 2 : 0.0;
    std::vector<float> stored(positions_.size());
    for (size_t i = 0; i < positions_.size(); ++i) stored[i] = static_cast<float>(positions_[i] - centre[i % 3]);
    std::vector<double>().swap(positions_);

    tinygltf::Primitive prim;
    std::vector<double> min, max;
    bounds(stored, 3, min, max);
    prim.attributes["POSITION"] = addAccessor(m, addView(m, stored.data(), stored.size() * 4, kArrayBuffer),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices_, min, max);
    std::vector<float>().swap(stored);
    if (layout_.surface) {
      prim.attributes["NORMAL"] = addAccessor(m, addView(m, normals_.data(), normals_.size() * 4, kArrayBuffer),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices_);
      std::vector<float>().swap(normals_);
      prim.attributes["TEXCOORD_0"] = addAccessor(m, addView(m, texCoords_.data(), texCoords_.size() * 4, kArrayBuffer),
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, vertices_);
      std::vector<float>().swap(texCoords_);
    }

    int mode = 0;
    std::vector<uint32_t> idx = indices(&mode);
    int view = 0, type = 0;
    if (vertices_ <= 0xffff) {
      std::vector<uint16_t> shorts(idx.begin(), idx.end());
      view = addView(m, shorts.data(), shorts.size() * 2, kElementArrayBuffer);
      type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    } else {
      view = addView(m, idx.data(), idx.size() * 4, kElementArrayBuffer);
      type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    }
    prim.indices = addAccessor(m, view, type, TINYGLTF_TYPE_SCALAR, idx.size());
    prim.mode = mode;

    tinygltf::Mesh mesh;
    mesh.name = layout_.source.empty() ? "shapespline" : std::filesystem::path(layout_.source).stem().string();
    mesh.primitives.push_back(std::move(prim));
    mesh.extras = toValue(metadataJson(layout_.metadata));
    m.meshes.push_back(std::move(mesh));

    tinygltf::Node node;
    node.mesh = 0;
    node.name = m.meshes[0].name;
    node.translation = {centre[0], centre[1], centre[2]};
    m.nodes.push_back(std::move(node));
    tinygltf::Scene scene;
    scene.nodes = {0};
    m.scenes.push_back(std::move(scene));
    m.defaultScene = 0;
    return m;
  }

  // .gltf: the JSON from tinygltf with an empty buffer, then that buffer pointed at the .bin.
  void writeGltf(tinygltf::Model& model) {
    std::vector<unsigned char> data;
    data.swap(model.buffers[0].data);
    std::ostringstream os;
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&model, os, true, false)) {
      throw OutputWriteError(out_.option(), out_.target().string(), "tinygltf could not write the .gltf");
    }
    nlohmann::json doc = nlohmann::json::parse(os.str());
    nlohmann::json& buffer = doc.at("buffers").at(0);
    buffer["uri"] = uriOf(bin_->target().filename().string());
    buffer["byteLength"] = data.size();
    out_.write(doc.dump(2) + "\n");
    bin_->write(data.data(), data.size());
  }

  AtomicFile& out_;
  AtomicFile* bin_;
  SampleLayout layout_;
  std::optional<WeldedNumbering> numbering_;
  std::optional<WeldedVertexStream> stream_;
  uint64_t vertices_ = 0;
  std::vector<double> positions_;
  std::vector<float> normals_, texCoords_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeGltfWriter(AtomicFile& out, AtomicFile* bin) {
  return std::make_unique<GltfWriter>(out, bin);
}

}  // namespace shapespline::io
