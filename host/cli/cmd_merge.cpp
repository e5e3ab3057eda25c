// `shapespline merge -o OUT SHARD...`: joins the outputs of `sample --shard K/N` (given in shard
// order) into the file the unsharded job writes. OBJ: vertex references renumbered (shards use
// relative indices, so plain `cat` works too); PLY: counts summed, vertex blocks concatenated,
// then every shard's faces/edges with its vertex offset; raw: bytes concatenated and the sidecar
// rewritten; CSV: the header once.
#include "cli/common.h"
#include "io/atomic_file.h"
#include "io/sample_writer.h"

#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

namespace shapespline::cli {
namespace {

struct MergeArgs {
  std::string out;
  std::vector<std::string> inputs;
};

std::string slurp(const std::string& path, size_t index) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("SHARD[" + std::to_string(index) + "]", path, "cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// OBJ: absolute positive indices are offset by the vertices of earlier files; negative (relative)
// ones stay as they are.
void mergeObj(const MergeArgs& a, io::AtomicFile& out) {
  long long offset = 0;
  for (size_t f = 0; f < a.inputs.size(); ++f) {
    const std::string text = slurp(a.inputs[f], f);
    long long vertices = 0;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("v ", 0) == 0) ++vertices;
      if (offset != 0 && (line.rfind("f ", 0) == 0 || line.rfind("l ", 0) == 0)) {
        std::string o(1, line[0]);
        std::istringstream ls(line.substr(2));
        std::string tok;
        while (ls >> tok) {
          o += ' ';
          size_t pos = 0;
          while (pos <= tok.size()) {
            const size_t slash = tok.find('/', pos);
            const std::string part = tok.substr(pos, slash == std::string::npos ? std::string::npos : slash - pos);
            if (!part.empty()) {
              const long long idx = std::stoll(part);
              o += std::to_string(idx > 0 ? idx + offset : idx);
            }
            if (slash == std::string::npos) break;
            o += '/';
            pos = slash + 1;
          }
        }
        line = o;
      }
      if (f > 0 && line.rfind("#", 0) == 0) continue;
      out.write(line);
      out.write("\n", 1);
    }
    offset += vertices;
  }
}

struct PlyFile {
  std::string header, data;
  size_t vertices = 0, faces = 0, edges = 0, vertexBytes = 0;
};

PlyFile readPly(const std::string& path, size_t index) {
  PlyFile p;
  std::string all = slurp(path, index);
  const size_t end = all.find("end_header\n");
  const std::string field = "SHARD[" + std::to_string(index) + "]";
  if (all.rfind("ply\n", 0) != 0 || end == std::string::npos) throw InputError(field, path, "not a PLY file");
  p.header = all.substr(0, end + 11);
  p.data = all.substr(end + 11);
  std::istringstream in(p.header);
  std::string line, element;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format" && line.find("binary_little_endian") == std::string::npos) throw InputError(field, path, "not binary little endian");
    if (w == "element") {
      size_t n = 0;
      ls >> element >> n;
      if (element == "vertex") p.vertices = n;
      else if (element == "face") p.faces = n;
      else if (element == "edge") p.edges = n;
      else throw InputError(field, path, "unexpected element '" + element + "'");
    } else if (w == "property" && element == "vertex") {
      std::string type;
      ls >> type;
      p.vertexBytes += type == "double" ? 8 : 4;
    }
  }
  if (p.data.size() != p.vertices * p.vertexBytes + p.faces * 13 + p.edges * 8) {
    throw InputError(field, path, "size does not match the header (not written by shapespline?)");
  }
  return p;
}

void mergePly(const MergeArgs& a, io::AtomicFile& out) {
  std::vector<PlyFile> files;
  size_t v = 0, f = 0, e = 0;
  for (size_t i = 0; i < a.inputs.size(); ++i) {
    files.push_back(readPly(a.inputs[i], i));
    v += files.back().vertices;
    f += files.back().faces;
    e += files.back().edges;
  }
  std::istringstream in(files[0].header);
  std::string line, header;
  while (std::getline(in, line)) {
    if (line.rfind("comment shard", 0) == 0) continue;
    if (line.rfind("element vertex", 0) == 0) line = "element vertex " + std::to_string(v);
    if (line.rfind("element face", 0) == 0) line = "element face " + std::to_string(f);
    if (line.rfind("element edge", 0) == 0) line = "element edge " + std::to_string(e);
    header += line + "\n";
  }
  out.write(header);
  for (const auto& p : files) out.write(p.data.data(), p.vertices * p.vertexBytes);
  uint32_t offset = 0;
  for (const auto& p : files) {
    const char* c = p.data.data() + p.vertices * p.vertexBytes;
    const size_t records = p.faces ? p.faces : p.edges, size = p.faces ? 13 : 8, skip = p.faces ? 1 : 0;
    for (size_t r = 0; r < records; ++r, c += size) {
      char rec[13];
      std::memcpy(rec, c, size);
      for (size_t k = 0; k < (size - skip) / 4; ++k) {
        uint32_t idx;
        std::memcpy(&idx, rec + skip + 4 * k, 4);
        idx += offset;
        std::memcpy(rec + skip + 4 * k, &idx, 4);
      }
      out.write(rec, size);
    }
    offset += static_cast<uint32_t>(p.vertices);
  }
}

void mergeRaw(const MergeArgs& a, io::AtomicFile& out, io::AtomicFile& sidecar) {
  nlohmann::json merged;
  size_t items = 0, points = 0, values = 0, bytes = 0;
  for (size_t i = 0; i < a.inputs.size(); ++i) {
    const std::string data = slurp(a.inputs[i], i);
    nlohmann::json side = readJsonFile(a.inputs[i] + ".json", "SHARD[" + std::to_string(i) + "].json");
    if (i == 0) merged = side;
    else if (side["items"]["first"].get<size_t>() != merged["items"]["first"].get<size_t>() + items) {
      throw InputError("SHARD[" + std::to_string(i) + "]", a.inputs[i], "shards must be given in order, without gaps");
    }
    out.write(data.data(), data.size());
    items += side["counts"]["items"].get<size_t>();
    points += side["counts"]["points"].get<size_t>();
    values += side["counts"]["values"].get<size_t>();
    bytes += data.size();
  }
  merged["data_file"] = out.target().filename().string();
  merged["counts"] = {{"items", items}, {"points", points}, {"values", values}, {"bytes", bytes}};
  merged["items"]["count"] = items;
  merged["shard"] = {{"index", 1}, {"count", 1}};
  sidecar.write(merged.dump(2) + "\n");
}

void runMerge(const MergeArgs& a) {
  const io::OutputFormat format = io::outputFormatFromPath(a.out, "-o");
  for (size_t i = 0; i < a.inputs.size(); ++i) {
    if (io::outputFormatFromPath(a.inputs[i], "SHARD[" + std::to_string(i) + "]") != format) {
      throw InputError("SHARD[" + std::to_string(i) + "]", a.inputs[i], "must have the output's extension");
    }
  }
  io::AtomicFile out(a.out, "-o");
  std::optional<io::AtomicFile> sidecar;
  switch (format) {
    case io::OutputFormat::Obj: mergeObj(a, out); break;
    case io::OutputFormat::Ply: mergePly(a, out); break;
    case io::OutputFormat::RawF32:
    case io::OutputFormat::RawF64:
      sidecar.emplace(a.out + ".json", "-o");
      mergeRaw(a, out, *sidecar);
      break;
    case io::OutputFormat::Csv:
      for (size_t i = 0; i < a.inputs.size(); ++i) {
        const std::string t = slurp(a.inputs[i], i);
        const size_t nl = t.find('\n');
        out.write(i == 0 || nl == std::string::npos ? t : t.substr(nl + 1));
      }
      break;
    case io::OutputFormat::Svg: throw InputError("-o", a.out, "SVG files do not merge");
  }
  out.commit();
  if (sidecar) sidecar->commit();
}

}  // namespace

void registerMerge(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  CLI::App* sub = app.add_subcommand("merge", "Join `sample --shard K/N` outputs (in shard order) into one file.");
  sub->add_option("SHARD", a->inputs, "shard files, K = 1..N in order")->required();
  sub->add_option("-o,--output", a->out, "merged file (.obj .ply .csv .f32 .f64)")->required();
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runMerge(*a); });
}

}  // namespace shapespline::cli
