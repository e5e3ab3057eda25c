// Writes the merge fuzz seed corpus: real shards of small jobs (a curve and a surface from
// examples/models, every mergeable format, 1-3 shards), written by the same writers `sample` uses,
// each packed as one input (merge_fuzz_format.h); plus shards in the wrong order, a shard given
// twice and a truncated shard, so that the fuzzer starts from both sides of every check.
// Usage: merge_fuzz_seeds OUT_DIR.
#include "seed_files.h"
#include "merge_fuzz_format.h"

#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>

namespace fs = std::filesystem;
using namespace shapespline;

namespace {

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

using shapespline::fuzz::writeSeed;

// One job (model, grid, format) as `sample` lays it out.
struct Job {
  std::optional<Curve> curve;
  std::optional<Surface> surface;
  io::SampleLayout layout;
  io::OutputFormat format = io::OutputFormat::Obj;
};

Job makeJob(const std::string& modelFile, io::OutputFormat format, int samples) {
  Job j;
  j.format = format;
  io::SampleLayout& l = j.layout;
  io::Model model = io::loadModelFile(fs::path(SHAPESPLINE_SOURCE_DIR) / "examples" / "models" / modelFile);
  l.source = "examples/models/" + modelFile;
  l.surface = std::holds_alternative<SurfaceModel>(model);
  l.fields = io::requiredFields(format, l.surface);
  l.precision = Precision::Double;  // the CPU sampler computes in fp64 (.f32 rounds on writing)
  if (l.surface) {
    j.surface.emplace(Surface::create(std::get<SurfaceModel>(std::move(model))));
    const auto items = surfaceGridItems(*j.surface);
    for (const auto& [i, k] : items) {
      if (l.spanU.empty() || l.spanU.back() != i) l.spanU.push_back(i);
      if (l.spanU.size() == 1) l.spanV.push_back(k);
    }
    l.itemsV = l.spanV.size();
    l.totalItems = items.size();
    for (int i : l.spanU) l.paramU.emplace_back(i, i + 1.0);
    for (int k : l.spanV) l.paramV.emplace_back(k, k + 1.0);
    l.samplesU = l.samplesV = samples;
    l.closedU = j.surface->model().closedU;
    l.closedV = j.surface->model().closedV;
    l.job = io::jobFingerprint(*j.surface, l, format);
  } else {
    j.curve.emplace(Curve::create(std::get<CurveModel>(std::move(model))));
    l.spanU = curveGridItems(*j.curve);
    l.spanV = {0};
    l.paramV = {{0.0, 0.0}};
    l.totalItems = l.spanU.size();
    l.dimension = j.curve->dimension();
    for (int s : l.spanU) l.paramU.emplace_back(j.curve->parameterOf(s, 0.0), j.curve->parameterOf(s, 1.0));
    l.samplesU = samples;
    l.samplesV = 1;
    l.closed = j.curve->model().closed;
    l.job = io::jobFingerprint(j.curve->model(), l, format);
  }
  return j;
}

// Shard k of n of the job, written to `path` (and its sidecar) by the format's writer.
void writeShard(Job& j, int k, int n, const fs::path& path) {
  io::SampleLayout l = j.layout;
  l.shardIndex = k;
  l.shardCount = n;
  const size_t t = l.totalItems, nn = static_cast<size_t>(n);
  l.firstItem = t / nn * static_cast<size_t>(k - 1) + t % nn * static_cast<size_t>(k - 1) / nn;
  l.itemCount = t / nn * static_cast<size_t>(k) + t % nn * static_cast<size_t>(k) / nn - l.firstItem;
  io::AtomicFile out(path, "-o");
  std::optional<io::AtomicFile> sidecar;
  const bool raw = j.format == io::OutputFormat::RawF32 || j.format == io::OutputFormat::RawF64;
  if (raw) sidecar.emplace(path.string() + ".json", "-o");
  auto writer = io::makeSampleWriter(j.format, out, sidecar ? &*sidecar : nullptr);
  writer->begin(l);
  if (l.itemCount > 0) {
    GridSpec grid;
    grid.samplesU = l.samplesU;
    grid.samplesV = l.samplesV;
    grid.firstItem = l.firstItem;
    grid.itemCount = l.itemCount;
    auto consume = [&](const GridChunk& c) { writer->consume(c); };
    for (const auto& [a, b] : io::streamedItemRanges(j.format, l)) {  // a welded shard's context too
      grid.firstItem = a;
      grid.itemCount = b - a;
      if (j.curve) sampleCurveGrid(*j.curve, grid, l.fields, consume, {.threads = 1});
      else sampleSurfaceGrid(*j.surface, grid, l.fields, consume, {.threads = 1});
    }
  }
  writer->finish();
  out.commit();
  if (sidecar) sidecar->commit();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: merge_fuzz_seeds OUT_DIR\n");
    return 2;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out);
    const fs::path work = out / ".work";
    fs::create_directories(work);
    size_t seeds = 0;
    const io::OutputFormat formats[5] = {io::OutputFormat::Obj, io::OutputFormat::Ply, io::OutputFormat::Csv,
                                         io::OutputFormat::RawF64, io::OutputFormat::RawF32};
    for (int f = 0; f < 5; ++f) {
      for (const auto& [model, samples] : {std::pair{"butterfly_aeb.json", 3}, std::pair{"surface_aeb.json", 2}}) {
        Job job = makeJob(model, formats[f], samples);
        for (int n = 1; n <= 3; ++n) {
          test::MergeFuzzInput in;
          in.format = f;
          for (int k = 1; k <= n; ++k) {
            std::string name(1, 'p');  // (not "p" + std::string: GCC 12 warns falsely, -Wrestrict)
            name += std::to_string(k) + "." + test::kMergeFuzzExtensions[f];
            const fs::path p = work / name;
            writeShard(job, k, n, p);
            test::MergeFuzzShard s;
            s.data = readFile(p);
            if (in.raw()) {
              s.sidecar = readFile(p.string() + ".json");
              s.hasSidecar = true;
            }
            in.shards.push_back(std::move(s));
          }
          const std::string base = std::string(test::kMergeFuzzExtensions[f]) + "_" +
                                   fs::path(model).stem().string() + "_" + std::to_string(n);
          writeSeed(out / (base + "_ok"), test::encodeMergeFuzzInput(in));
          ++seeds;
          if (n >= 2) {
            test::MergeFuzzInput swapped = in, twice = in, cut = in;
            std::swap(swapped.shards[0], swapped.shards[1]);
            twice.shards[1] = twice.shards[0];
            cut.shards.back().data.resize(cut.shards.back().data.size() * 2 / 3);
            writeSeed(out / (base + "_swapped"), test::encodeMergeFuzzInput(swapped));
            writeSeed(out / (base + "_twice"), test::encodeMergeFuzzInput(twice));
            writeSeed(out / (base + "_cut"), test::encodeMergeFuzzInput(cut));
            seeds += 3;
          }
        }
      }
    }
    fs::remove_all(work);
    std::printf("merge_fuzz_seeds: %zu inputs -> %s\n", seeds, out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "merge_fuzz_seeds: %s\n", e.what());
    return 1;
  }
}
