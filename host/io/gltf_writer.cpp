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
// Serialized by io/gltf_model.h writeGltfModel: .glb one file; .gltf and its .bin through two
// AtomicFiles of the same OutputSet, so they appear together or not at all.
#include <shapespline/io/gltf_model.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/welded_mesh.h>
#include <shapespline/version.h>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace shapespline::io {

std::filesystem::path gltfBufferPath(const std::filesystem::path& gltf) {
  std::filesystem::path p = gltf;
  return p.replace_extension(".bin");
}

namespace {

constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;

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
    writeGltfModel(model, out_, bin_);
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
    gltfBounds(stored, 3, min, max);
    prim.attributes["POSITION"] = addGltfAccessor(m, addGltfView(m, stored.data(), stored.size() * 4, kArrayBuffer),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices_, min, max);
    std::vector<float>().swap(stored);
    if (layout_.surface) {
      prim.attributes["NORMAL"] = addGltfAccessor(m, addGltfView(m, normals_.data(), normals_.size() * 4, kArrayBuffer),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices_);
      std::vector<float>().swap(normals_);
      prim.attributes["TEXCOORD_0"] = addGltfAccessor(m, addGltfView(m, texCoords_.data(), texCoords_.size() * 4, kArrayBuffer),
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, vertices_);
      std::vector<float>().swap(texCoords_);
    }

    int mode = 0;
    std::vector<uint32_t> idx = indices(&mode);
    int view = 0, type = 0;
    if (vertices_ <= 0xffff) {
      std::vector<uint16_t> shorts(idx.begin(), idx.end());
      view = addGltfView(m, shorts.data(), shorts.size() * 2, kElementArrayBuffer);
      type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    } else {
      view = addGltfView(m, idx.data(), idx.size() * 4, kElementArrayBuffer);
      type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    }
    prim.indices = addGltfAccessor(m, view, type, TINYGLTF_TYPE_SCALAR, idx.size());
    prim.mode = mode;

    tinygltf::Mesh mesh;
    mesh.name = layout_.source.empty() ? "shapespline" : std::filesystem::path(layout_.source).stem().string();
    mesh.primitives.push_back(std::move(prim));
    mesh.extras = gltfValue(metadataJson(layout_.metadata));
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
