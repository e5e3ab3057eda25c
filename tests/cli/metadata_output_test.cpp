// Issue 15 (requirement 6): the job metadata of `sample`, read back by readers we did not write:
// /usr/bin/python3's json and hashlib read the raw sidecar OUT.json and the OUT.npy.json every .npy
// now has, and check the model's SHA-256 (of the file's bytes), λ, α per vertex, the singular
// (α = 1) vertices, the device, both precisions, the grid and the tool version; xml.etree reads the
// SVG's <metadata>. Sharded raw and .npy jobs merge with the metadata intact (the merged sidecar is
// the unsharded one but for data_file), and shards whose metadata differ are refused by the key.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

#define REQUIRE_PYTHON() \
  if (!fs::exists(kPython)) GTEST_SKIP() << kPython << " is missing"

// An α-EB curve with α = 1 at vertices 1 and 4, an α-EB surface with α = 1 at (0, 2) and (2, 1).
constexpr const char* kCurve = R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": -1.75,
 "closed": false, "points": [[0, 0], [1, 2], [3, 3], [5, 1], [6, 4], [8, 3]],
 "alpha": [0.5, 1, 0.25, 0.75, 1, 0.625]}
)";
constexpr const char* kSurface = R"({"kind": "surface", "construction": "alpha_eb", "degree": 4, "lambda": 0.5,
 "closed": [false, false],
 "points": [[[0, 0, 0], [0, 1, 0.5], [0, 2, 0], [0, 3, 0]],
            [[1, 0, 0.5], [1, 1, 1.5], [1, 2, 0.5], [1, 3, 0]],
            [[2, 0, 0], [2, 1, 0.5], [2, 2, 2], [2, 3, 0.5]],
            [[3, 0, 0], [3, 1, 0], [3, 2, 0.5], [3, 3, 1]]],
 "alpha": [[0.5, 0.5, 1, 0.5], [0.25, 0.5, 0.5, 0.5], [0.5, 1, 0.5, 0.5], [0.5, 0.5, 0.5, 0.125]]}
)";

// Writes the models into `dir` (their names carry a space and a quote: escaped, not broken).
void writeModels(const ScratchDir& dir) {
  writeText(dir / "a curve's.json", kCurve);
  writeText(dir / "surface.json", kSurface);
}

CliResult sample(const ScratchDir& dir, const std::string& model, const std::string& out, const std::string& opts) {
  return runCli("sample " + quote(model) + " -o " + quote(out) + " " + opts + " -q", dir.path(), dir.path());
}

void sampleOk(const ScratchDir& dir, const std::string& model, const std::string& out, const std::string& opts) {
  const CliResult r = sample(dir, model, out, opts);
  ASSERT_EQ(r.rc, 0) << out << ": " << r.err;
}

// argv: sidecar, model file (as given to sample), grid, output precision, device, version line.
constexpr const char* kSidecarCheck = R"PY(
import hashlib, json, sys
side, model, grid, outp, device, version = sys.argv[1:7]
doc = json.load(open(side, encoding="utf-8"))
m = doc["metadata"]
src = json.load(open(model))
assert m["tool"] == "shapespline", m["tool"]
assert version == "shapespline %s (commit %s)" % (m["tool_version"], m["tool_commit"]), (version, m)
assert m["model_file"] == model, (m["model_file"], model)
assert m["model_sha256"] == hashlib.sha256(open(model, "rb").read()).hexdigest(), m["model_sha256"]
assert m["kind"] == src["kind"] and m["construction"] == src["construction"], m
assert m["degree"] == src["degree"], m["degree"]
assert m["lambda"] == src["lambda"], (m["lambda"], src["lambda"])
assert "mu" not in m and "order" not in m, m
assert m["alpha"] == src["alpha"], (m["alpha"], src["alpha"])
if src["kind"] == "curve":
    want = [i for i, a in enumerate(src["alpha"]) if a == 1]
else:
    want = [[i, j] for i, row in enumerate(src["alpha"]) for j, a in enumerate(row) if a == 1]
assert want, "the test model has singular vertices"
assert m["singular_vertices"] == want, (m["singular_vertices"], want)
assert m["device"] == device == doc["device"], (m["device"], device, doc["device"])
assert m["computed_precision"] == doc["computed_precision"], m
if device == "cpu":
    assert m["computed_precision"] == "double", m
assert m["output_precision"] == outp, (m["output_precision"], outp)
assert m["grid"] == grid, (m["grid"], grid)
assert doc["format_version"] == 4, doc["format_version"]
assert "shard" not in m, m
print("OK")
)PY";

std::string versionLine(const ScratchDir& dir) {
  const CliResult r = runCli("--version", dir.path());
  std::string v = r.out;
  while (!v.empty() && (v.back() == '\n' || v.back() == '\r')) v.pop_back();
  return v;
}

TEST(MetadataOutput, RawAndNpySidecarsCarryTheJobMetadata) {
  REQUIRE_PYTHON();
  ScratchDir dir("metadata_raw");
  writeModels(dir);
  const std::string version = versionLine(dir);
  ASSERT_TRUE(contains(version, "shapespline ")) << version;
  struct Case {
    std::string model, out, opts, grid, precision;
  };
  const Case cases[] = {
      {"a curve's.json", "c.f32", "--samples 5", "5", "float"},
      {"a curve's.json", "c.npy", "--samples 5 --precision float", "5", "float"},
      {"a curve's.json", "c64.npy", "--samples 6 --derivatives", "6", "double"},
      {"surface.json", "s.f64", "--grid 3x4 --normals --precision float", "3x4", "double"},  // .f64 stores fp64
      {"surface.json", "s.npy", "--grid 3x4 --precision float", "3x4", "float"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.out);
    sampleOk(dir, c.model, c.out, c.opts + " --device cpu");
    ASSERT_TRUE(fs::exists(dir / (c.out + ".json"))) << "every raw and .npy output has its sidecar";
    expectPythonOk(dir, kSidecarCheck, {c.out + ".json", c.model, c.grid, c.precision, "cpu", version});
  }
  // The .npy's sidecar is the raw one of the same job but for data_file and the dtype it names.
  const json npy = json::parse(readText(dir / "c.npy.json")), raw = json::parse(readText(dir / "c.f32.json"));
  EXPECT_EQ(npy["metadata"], raw["metadata"]);
  EXPECT_EQ(npy["data_file"], "c.npy");
  EXPECT_EQ(npy["dtype"], "float32");
}

TEST(MetadataOutput, GpuSidecarNamesTheDevice) {
  REQUIRE_PYTHON();
  REQUIRE_VULKAN();
  ScratchDir dir("metadata_gpu");
  writeModels(dir);
  sampleOk(dir, "surface.json", "g.f32", "--grid 4x4 --device vulkan --precision float --require-device");
  const json side = json::parse(readText(dir / "g.f32.json"));
  ASSERT_NE(side["device"], "cpu");
  EXPECT_EQ(side["computed_precision"], "float");
  expectPythonOk(dir, kSidecarCheck, {"g.f32.json", "surface.json", "4x4", "float", side["device"].get<std::string>(),
                              versionLine(dir)});
}

// The merged sidecar equals the unsharded job's but for its data_file name.
void expectSidecarOfWhole(const ScratchDir& dir, const std::string& merged, const std::string& whole) {
  std::string text = readText(dir / (whole + ".json"));
  const std::string from = "\"" + whole + "\"";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "\"" + merged + "\"");
  EXPECT_EQ(readText(dir / (merged + ".json")), text);
}

CliResult mergeIn(const ScratchDir& dir, const std::string& out, const std::vector<std::string>& shards) {
  std::string args = "merge -o " + quote(out);
  for (const auto& s : shards) args += " " + quote(s);
  return runCli(args, dir.path(), dir.path());
}

TEST(MetadataOutput, ShardsMergeWithTheMetadataIntact) {
  REQUIRE_PYTHON();
  ScratchDir dir("metadata_merge");
  writeModels(dir);
  const std::string version = versionLine(dir);
  for (const std::string ext : {"f32", "npy"}) {
    SCOPED_TRACE(ext);
    const std::string opts = "--grid 3x2 --precision float --device cpu";
    sampleOk(dir, "surface.json", "whole." + ext, opts);
    std::vector<std::string> shards;
    for (int k = 1; k <= 4; ++k) {
      shards.push_back("part" + std::to_string(k) + "." + ext);
      sampleOk(dir, "surface.json", shards.back(), opts + " --shard " + std::to_string(k) + "/4");
      // Every shard carries the whole job's metadata (its own part is in "shard" and "items").
      EXPECT_EQ(json::parse(readText(dir / (shards.back() + ".json")))["metadata"],
                json::parse(readText(dir / ("whole." + ext + ".json")))["metadata"]);
    }
    const CliResult r = mergeIn(dir, "merged." + ext, shards);
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(readText(dir / ("merged." + ext)), readText(dir / ("whole." + ext)));
    expectSidecarOfWhole(dir, "merged." + ext, "whole." + ext);
    expectPythonOk(dir, kSidecarCheck, {"merged." + ext + ".json", "surface.json", "3x2", "float", "cpu", version});
  }
}

// A net of more than 4096 vertices (here 70 x 70 from a .npy) is summarised in the metadata, not
// listed: count, shape, range and the number of α = 1 vertices, as numpy counts them; its shards
// merge into the unsharded file with the same sidecar.
constexpr const char* kWriteBigNet = R"PY(
import json, numpy as np
n = 70
u, v = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float), indexing="ij")
np.save("net.npy", np.stack([u, v, np.sin(u / 7) * np.cos(v / 5)], axis=-1))
alpha = np.full((n, n), 0.5)
alpha[3, 4] = alpha[60, 2] = alpha[69, 69] = 1.0
alpha[10, 11] = 0.125
np.save("alpha.npy", alpha)
json.dump({"kind": "surface", "construction": "alpha_eb", "degree": 5, "lambda": 0.25,
           "points": {"npy": "net.npy"}, "alpha": {"npy": "alpha.npy"}}, open("big.json", "w"))
print("OK")
)PY";
constexpr const char* kBigSidecarCheck = R"PY(
import json, sys, numpy as np
m = json.load(open(sys.argv[1]))["metadata"]
alpha = np.load("alpha.npy")
want = {"values": int(alpha.size), "shape": list(alpha.shape), "min": float(alpha.min()), "max": float(alpha.max())}
assert m["alpha"] == want, (m["alpha"], want)
assert m["singular_vertices"] == {"count": int((alpha == 1).sum())}, m["singular_vertices"]
print("OK")
)PY";

TEST(MetadataOutput, LargeNetsSummariseAlpha) {
  REQUIRE_PYTHON();
  ScratchDir dir("metadata_big_alpha");
  expectPythonOk(dir, kWriteBigNet, {});
  const std::string opts = "--grid 2x2 --device cpu";
  sampleOk(dir, "big.json", "whole.f64", opts);
  expectPythonOk(dir, kBigSidecarCheck, {"whole.f64.json"});
  EXPECT_LT(fs::file_size(dir / "whole.f64.json"), 8192u) << "the sidecar stays small";
  std::vector<std::string> shards;
  for (int k = 1; k <= 2; ++k) {
    shards.push_back("part" + std::to_string(k) + ".f64");
    sampleOk(dir, "big.json", shards.back(), opts + " --shard " + std::to_string(k) + "/2");
  }
  const CliResult r = mergeIn(dir, "merged.f64", shards);
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(readText(dir / "merged.f64"), readText(dir / "whole.f64"));
  expectSidecarOfWhole(dir, "merged.f64", "whole.f64");
}

TEST(MetadataOutput, ShardsWithOtherMetadataAreRefusedByKey) {
  ScratchDir dir("metadata_refused");
  writeModels(dir);
  // The same model under another name: the same job fingerprint, another model_file.
  writeText(dir / "copy.json", kSurface);
  const std::string opts = "--grid 2 --device cpu";
  sampleOk(dir, "surface.json", "p1.f64", opts + " --shard 1/2");
  sampleOk(dir, "copy.json", "p2.f64", opts + " --shard 2/2");
  const CliResult r = mergeIn(dir, "m.f64", {"p1.f64", "p2.f64"});
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "SHARD[2]")) << r.err;
  EXPECT_TRUE(contains(r.err, "metadata.model_file")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "m.f64"));
  EXPECT_FALSE(fs::exists(dir / "m.f64.json"));

  // A sidecar whose metadata was edited by hand: refused naming the key, before any data is copied.
  sampleOk(dir, "surface.json", "q2.f64", opts + " --shard 2/2");
  fs::remove(dir / "q2.f64.shard.json");  // its shard record would refuse any edit first (shard_resume_test)
  json side = json::parse(readText(dir / "q2.f64.json"));
  side["metadata"]["singular_vertices"] = json::array();
  writeText(dir / "q2.f64.json", side.dump(2));
  const CliResult edited = mergeIn(dir, "m.f64", {"p1.f64", "q2.f64"});
  EXPECT_EQ(edited.rc, 2) << edited.err;
  EXPECT_TRUE(contains(edited.err, "metadata.singular_vertices")) << edited.err;
  side.erase("metadata");
  writeText(dir / "q2.f64.json", side.dump(2));
  const CliResult missing = mergeIn(dir, "m.f64", {"p1.f64", "q2.f64"});
  EXPECT_EQ(missing.rc, 2) << missing.err;
  EXPECT_TRUE(contains(missing.err, "metadata")) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "m.f64"));
}

// argv: svg, model file.
constexpr const char* kSvgCheck = R"PY(
import hashlib, json, sys
import xml.etree.ElementTree as ET
svg, model = sys.argv[1:3]
root = ET.parse(svg).getroot()
found = root.findall("{http://www.w3.org/2000/svg}metadata")
assert len(found) == 1, found
m = json.loads(found[0].text)
assert m["model_sha256"] == hashlib.sha256(open(model, "rb").read()).hexdigest(), m
assert m["singular_vertices"] == [1, 4], m["singular_vertices"]
assert m["grid"] == "9" and m["device"] == "cpu", m
print("OK")
)PY";

TEST(MetadataOutput, SvgCarriesTheMetadataElement) {
  REQUIRE_PYTHON();
  ScratchDir dir("metadata_svg");
  writeModels(dir);
  sampleOk(dir, "a curve's.json", "c.svg", "--samples 9 --device cpu");
  expectPythonOk(dir, kSvgCheck, {"c.svg", "a curve's.json"});
  expectFiniteOutput(dir / "c.svg", "c.svg");
}

}  // namespace
}  // namespace shapespline::test
