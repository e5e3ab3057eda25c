#include <shapespline/io/gltf_model.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <exception>
#include <limits>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>

namespace shapespline::io {
namespace {

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

}  // namespace

tinygltf::Value gltfValue(const nlohmann::json& j) {
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
      for (const auto& e : j) a.push_back(gltfValue(e));
      return tinygltf::Value(std::move(a));
    }
    case nlohmann::json::value_t::object: {
      tinygltf::Value::Object o;
      for (const auto& [k, v] : j.items()) o.emplace(k, gltfValue(v));
      return tinygltf::Value(std::move(o));
    }
    default: return tinygltf::Value();
  }
}

int addGltfView(tinygltf::Model& m, const void* data, size_t bytes, int target) {
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

int addGltfAccessor(tinygltf::Model& m, int view, int componentType, int type, size_t count,
                    std::vector<double> min, std::vector<double> max) {
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

void gltfBounds(const std::vector<float>& values, int k, std::vector<double>& min, std::vector<double>& max) {
  min.assign(static_cast<size_t>(k), std::numeric_limits<double>::infinity());
  max.assign(static_cast<size_t>(k), -std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < values.size(); ++i) {
    const size_t c = i % static_cast<size_t>(k);
    min[c] = std::min(min[c], static_cast<double>(values[i]));
    max[c] = std::max(max[c], static_cast<double>(values[i]));
  }
}

void writeGltfModel(tinygltf::Model& model, AtomicFile& out, AtomicFile* bin) {
  tinygltf::TinyGLTF gltf;
  if (!bin) {
    AtomicFileBuf buf(out);
    std::ostream os(&buf);
    const bool ok = gltf.WriteGltfSceneToStream(&model, os, false, true);
    os.flush();
    buf.rethrow();
    if (!ok || !os) throw OutputWriteError(out.option(), out.target().string(), "tinygltf could not write the .glb");
    return;
  }
  std::vector<unsigned char> data;
  data.swap(model.buffers[0].data);
  std::ostringstream os;
  if (!gltf.WriteGltfSceneToStream(&model, os, true, false)) {
    throw OutputWriteError(out.option(), out.target().string(), "tinygltf could not write the .gltf");
  }
  nlohmann::json doc = nlohmann::json::parse(os.str());
  nlohmann::json& buffer = doc.at("buffers").at(0);
  buffer["uri"] = uriOf(bin->target().filename().string());
  buffer["byteLength"] = data.size();
  out.write(doc.dump(2) + "\n");
  bin->write(data.data(), data.size());
}

}  // namespace shapespline::io
