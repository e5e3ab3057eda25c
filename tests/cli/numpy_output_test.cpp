// Issue 15 (requirements 4 and 5), checked by readers we did not write: numpy (Debian
// python3-numpy, run by /usr/bin/python3) loads `sample -o OUT.npy` memory-mapped, and its dtype,
// shape, field names and data bytes equal the raw .f32/.f64 output of the same job; sharded .npy
// files merge into the unsharded file byte for byte (and their sidecars into its OUT.npy.json); every number of a float / double OBJ and CSV
// reads back (Python's float() then numpy.float32 / float64) to exactly the raw output's value, with
// the digits of numpy's own shortest round-trip form (at most 9 / 17 significant digits).
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Skips unless Debian's interpreter with numpy is there (CI installs both: scripts/setup.sh).
bool numpyMissing(std::string* why) {
  if (!fs::exists(kPython)) {
    *why = std::string(kPython) + " is missing (install python3-numpy: scripts/setup.sh)";
    return true;
  }
  if (std::system((std::string(kPython) + " -c 'import numpy' >/dev/null 2>&1").c_str()) != 0) {
    *why = std::string(kPython) + " has no numpy (install python3-numpy: scripts/setup.sh)";
    return true;
  }
  return false;
}

#define REQUIRE_NUMPY()                        \
  do {                                         \
    std::string why_;                          \
    if (numpyMissing(&why_)) GTEST_SKIP() << why_; \
  } while (0)

void sampleTo(const ScratchDir& dir, const std::string& modelName, const std::string& name, const std::string& opts) {
  const CliResult r = runCli("sample " + quote(exampleModel(modelName)) + " -o " + quote((dir / name).string()) + " " + opts +
                                 " --device cpu -q",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << name << ": " << r.err;
}

// argv: npy raw sidecar-of-raw field names...
constexpr const char* kNpyCheck = R"PY(
import json, sys
import numpy as np
npy, raw, side, want = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split(",")
meta = json.load(open(side))
a = np.load(npy, mmap_mode="r")
assert isinstance(a, np.memmap), type(a)
assert a.offset % 64 == 0, a.offset
base = np.dtype("<f8" if meta["dtype"] == "float64" else "<f4")
assert list(a.dtype.names) == want, (a.dtype.names, want)
assert a.dtype.names == tuple(meta["fields"]), (a.dtype.names, meta["fields"])
for f in want:
    sub = a.dtype.fields[f][0]
    assert sub.base == base and sub.shape == (3,), (f, sub)
assert a.shape == (meta["counts"]["points"],), (a.shape, meta["counts"])
data = open(raw, "rb").read()
assert a.tobytes() == data, "data bytes differ from the raw output"
assert open(npy, "rb").read()[a.offset:] == data
p = np.asarray(a["point"])
assert p.shape == (a.shape[0], 3) and p.dtype == base
print("OK", a.shape, a.dtype)
)PY";

struct NpyCase {
  const char* model;
  const char* opts;
  const char* fields;
};

TEST(NumpyOutput, LoadsMemoryMappedAndEqualsRawBytes) {
  REQUIRE_NUMPY();
  ScratchDir dir("npy_raw");
  const NpyCase cases[] = {
      {"open_aeb.json", "--samples 7 --derivatives", "point,d1,d2"},
      {"surface_aeb.json", "--grid 3x4 --derivatives --normals", "point,du,dv,duu,duv,dvv,normal"},
      {"bspline_surface.json", "--grid 2x3 --normals", "point,normal"},
  };
  int n = 0;
  for (const NpyCase& c : cases) {
    for (const char* precision : {"float", "double"}) {
      const std::string stem = "j" + std::to_string(n++), raw = stem + (precision[0] == 'f' ? ".f32" : ".f64");
      const std::string opts = std::string(c.opts) + " --precision " + precision;
      sampleTo(dir, c.model, stem + ".npy", opts);
      sampleTo(dir, c.model, raw, opts);
      // Every .npy has the raw sidecar OUT.npy.json (its job metadata; docs/cli.md).
      EXPECT_TRUE(fs::exists(dir / (stem + ".npy.json"))) << "an unsharded .npy has its sidecar too";
      SCOPED_TRACE(std::string(c.model) + " " + opts);
      expectPythonOk(dir, kNpyCheck, {(dir / (stem + ".npy")).string(), (dir / raw).string(), (dir / (raw + ".json")).string(),
                              c.fields});
    }
  }
}

TEST(NumpyOutput, ShardsAreNpyFilesAndMergeByteForByte) {
  REQUIRE_NUMPY();
  ScratchDir dir("npy_shards");
  const std::string opts = "--grid 3x3 --derivatives --precision float";
  sampleTo(dir, "surface_aeb.json", "whole.npy", opts);
  sampleTo(dir, "surface_aeb.json", "whole.f32", opts);
  std::vector<std::string> shards;
  for (int k = 1; k <= 3; ++k) {
    const std::string name = "part" + std::to_string(k);
    sampleTo(dir, "surface_aeb.json", name + ".npy", opts + " --shard " + std::to_string(k) + "/3");
    sampleTo(dir, "surface_aeb.json", name + ".f32", opts + " --shard " + std::to_string(k) + "/3");
    ASSERT_TRUE(fs::exists(dir / (name + ".npy.json"))) << "a .npy shard carries the raw sidecar";
    expectPythonOk(dir, kNpyCheck, {(dir / (name + ".npy")).string(), (dir / (name + ".f32")).string(),
                            (dir / (name + ".f32.json")).string(), "point,du,dv,duu,duv,dvv"});
    shards.push_back((dir / (name + ".npy")).string());
  }
  std::string args = "merge -o " + quote((dir / "merged.npy").string());
  for (const auto& s : shards) args += " " + quote(s);
  const CliResult r = runCli(args, dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(readText(dir / "merged.npy"), readText(dir / "whole.npy"));
  // The merged sidecar is the unsharded one but for its data_file name.
  std::string wholeSide = readText(dir / "whole.npy.json");
  ASSERT_NE(wholeSide.find("\"whole.npy\""), std::string::npos);
  wholeSide.replace(wholeSide.find("\"whole.npy\""), 11, "\"merged.npy\"");
  EXPECT_EQ(readText(dir / "merged.npy.json"), wholeSide);

  // Out of order, and a shard whose header was altered: refused, nothing written.
  const CliResult swapped = runCli("merge -o " + quote((dir / "bad.npy").string()) + " " + quote(shards[1]) + " " +
                                       quote(shards[0]) + " " + quote(shards[2]),
                                   dir.path());
  EXPECT_EQ(swapped.rc, 2) << swapped.err;
  std::string bytes = readText(shards[1]);
  fs::remove(shards[1] + ".shard.json");  // its shard record would refuse any edit first (shard_resume_test)
  bytes[bytes.find("'<f4'")] = '"';
  writeText(shards[1], bytes);
  const CliResult tampered = runCli(args, dir.path());
  EXPECT_EQ(tampered.rc, 2) << tampered.err;
  EXPECT_TRUE(contains(tampered.err, "SHARD[2]")) << tampered.err;
  EXPECT_TRUE(contains(tampered.err, ".npy header")) << tampered.err;
  EXPECT_FALSE(fs::exists(dir / "bad.npy"));
}

// argv: text file, kind (obj|csv), raw file, dtype (float32|float64), leading columns (csv).
constexpr const char* kDecimalCheck = R"PY(
import re, sys
import numpy as np
text, kind, raw, dtype, lead = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5])
t = np.float32 if dtype == "float32" else np.float64
limit = 9 if dtype == "float32" else 17
rec = np.fromfile(raw, dtype="<f4" if dtype == "float32" else "<f8")

def digits(tok):
    m = re.fullmatch(r"-?(\d*)\.?(\d*)(?:e[-+]?\d+)?", tok)
    assert m, tok
    d = (m.group(1) + m.group(2)).lstrip("0")
    if "." not in tok:
        d = d.rstrip("0")
    return max(len(d), 1)

def check(tok):
    v = t(float(tok))  # Python's parse, rounded to the file's precision
    shortest = np.format_float_scientific(v, unique=True, trim="-")
    assert digits(tok) <= limit, (tok, "has more than", limit, "significant digits")
    assert digits(tok) == digits(shortest), (tok, "is not the shortest form", shortest)
    return v

got = []
count = 0
for line in open(text):
    line = line.rstrip("\n")
    if kind == "obj":
        parts = line.split()
        if not parts or parts[0] not in ("v", "vt", "vn"):
            continue
        vals = [check(p) for p in parts[1:]]
        count += len(vals)
        if parts[0] in ("v", "vn"):
            got.append((parts[0], vals))
    else:
        if line[0].isalpha():
            continue
        cols = line.split(",")
        vals = [check(c) for c in cols[1:]]  # the first column is an integer index
        count += len(vals)
        got.extend(vals[lead - 1:])
if kind == "obj":
    # Records are point then normal (surfaces); curve OBJs have points only.
    flat = []
    v = [x for k, x in got if k == "v"]
    n = [x for k, x in got if k == "vn"]
    for i in range(len(v)):
        flat += v[i] + (n[i] if n else [])
    got = flat
if kind == "csv" and 3 * len(got) == 2 * rec.size:  # a 2-D curve: no z column, the raw z is 0
    rec = rec.reshape(-1, 3)
    assert not rec[:, 2].any()
    rec = rec[:, :2].ravel()
assert len(got) == rec.size, (len(got), rec.size)
bad = np.nonzero(np.asarray(got, dtype=t) != rec)[0]
assert bad.size == 0, ("value", bad[0], got[bad[0]], "differs from the raw record", rec[bad[0]])
print("OK", count, "numbers")
)PY";

TEST(ShortestDecimals, TextOutputsReadBackToTheRawValues) {
  REQUIRE_NUMPY();
  ScratchDir dir("shortest");
  struct TextCase {
    const char* model;
    const char* ext;
    const char* opts;
    const char* lead;  // csv: columns before the fields, the integer index included
  };
  const TextCase cases[] = {
      {"surface_aeb.json", "obj", "--grid 4x3", "0"},
      {"open_aeb.json", "obj", "--samples 9", "0"},
      {"surface_aeb.json", "csv", "--grid 3x3 --derivatives --normals", "6"},
      {"open_aeb.json", "csv", "--samples 9 --derivatives", "3"},
  };
  int n = 0;
  for (const TextCase& c : cases) {
    for (const char* precision : {"float", "double"}) {
      const bool f = precision[0] == 'f';
      const std::string stem = "t" + std::to_string(n++), raw = stem + (f ? ".f32" : ".f64");
      // OBJ surfaces carry normals; the raw job has the same fields in the same order.
      const std::string rawOpts = std::string(c.opts) +
                                  (std::string(c.ext) == "obj" && std::string(c.model) == "surface_aeb.json" ? " --normals" : "");
      // Per item: the OBJ lists the points in the raw file's order.
      sampleTo(dir, c.model, stem + "." + c.ext,
               std::string(c.opts) + " --precision " + precision + (std::string(c.ext) == "obj" ? " --mesh-layout per-item" : ""));
      sampleTo(dir, c.model, raw, rawOpts + " --precision " + precision);
      SCOPED_TRACE(std::string(c.model) + " ." + c.ext + " " + precision);
      expectPythonOk(dir, kDecimalCheck, {(dir / (stem + "." + c.ext)).string(), c.ext, (dir / raw).string(),
                                  f ? "float32" : "float64", c.lead});
    }
  }
  // The float OBJ is the smaller one (it printed 17 digits before).
  sampleTo(dir, "surface_aeb.json", "f.obj", "--grid 8x8 --precision float");
  sampleTo(dir, "surface_aeb.json", "d.obj", "--grid 8x8 --precision double");
  EXPECT_LT(fs::file_size(dir / "f.obj"), fs::file_size(dir / "d.obj") * 3 / 4);
}

}  // namespace
}  // namespace shapespline::test
