// Issue 31 (binary control nets): a model file may name its points, alpha and weights as .npy
// arrays beside it. The arrays are written by numpy (Debian python3-numpy, the reader's reference),
// never by us: a referenced net samples to exactly the bytes of the same net written out in JSON
// (fp64 arrays; fp32 arrays as their float values), and every bad array is refused with exit 2,
// an error naming the key and the file, and no output.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Writes the models and arrays of these tests into argv[1] (a model folder) and argv[2] (a
// folder beside it, for the outside-the-folder cases).
constexpr const char* kMakeArrays = R"PY(
import json, os, sys
import numpy as np
d, outside = sys.argv[1], sys.argv[2]
n = 10
P = np.array([[(i, j, np.sin(0.7 * i) * np.cos(0.5 * j)) for j in range(n)] for i in range(n)], float)
al = np.random.default_rng(3).uniform(0.1, 1.0, (n, n))
def save(name, a, folder=d):
    np.save(os.path.join(folder, name), a)
save("net.npy", P)
save("net32.npy", P.astype(np.float32))
save("alpha.npy", al)
surface = {"kind": "surface", "construction": "alpha_eb", "degree": 5, "lambda": 0.25}
def model(name, **keys):
    json.dump(dict(surface, **keys), open(os.path.join(d, name), "w"))
model("inline.json", points=P.tolist(), alpha=al.tolist())
model("inline32.json", points=P.astype(np.float32).astype(float).tolist(), alpha=al.tolist())
model("ref.json", points={"npy": "net.npy"}, alpha={"npy": "alpha.npy"})
model("ref32.json", points={"npy": "net32.npy"}, alpha={"npy": "alpha.npy"})
# A rational curve: 2-D points and weights as arrays.
C = np.array([(np.cos(t), np.sin(2 * t)) for t in np.linspace(0, 3, 8)])
W = np.linspace(0.5, 2.0, 8)
save("curve.npy", C)
save("weights.npy", W)
knots = [0, 0, 0, 0, 0.2, 0.3, 0.5, 0.8, 1, 1, 1, 1]
curve = {"kind": "curve", "construction": "bspline", "order": 4, "knots": knots}
json.dump(dict(curve, points=C.tolist(), weights=W.tolist()), open(os.path.join(d, "curve_inline.json"), "w"))
json.dump(dict(curve, points={"npy": "curve.npy"}, weights={"npy": "weights.npy"}),
          open(os.path.join(d, "curve_ref.json"), "w"))
# Bad arrays, each in its own model (points unless named otherwise).
save("int.npy", P.astype(np.int64))
save("big_endian.npy", P.astype(">f8"))
save("fortran.npy", np.asfortranarray(P))
save("shape.npy", P[:, :, :2])
nan = P.copy(); nan[3, 4, 1] = np.nan
save("nan.npy", nan)
raw = open(os.path.join(d, "net.npy"), "rb").read()
open(os.path.join(d, "truncated.npy"), "wb").write(raw[:-8])
# A header that claims 10^12 elements, on a file of a few hundred bytes.
hdr = "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000, 1000000, 3), }"
hdr += " " * (117 - len(hdr)) + "\n"
open(os.path.join(d, "huge.npy"), "wb").write(b"\x93NUMPY\x01\x00" + len(hdr).to_bytes(2, "little") + hdr.encode() + raw[128:])
save("alpha_shape.npy", al[:, :5])
save("net.npy", P, outside)
os.symlink(os.path.join(outside, "net.npy"), os.path.join(d, "link.npy"))
for name in ["int", "big_endian", "fortran", "shape", "nan", "truncated", "huge", "link", "missing"]:
    model("bad_" + name + ".json", points={"npy": name + ".npy"}, alpha={"npy": "alpha.npy"})
model("bad_alpha_shape.json", points={"npy": "net.npy"}, alpha={"npy": "alpha_shape.npy"})
model("bad_dotdot.json", points={"npy": "../" + os.path.basename(outside) + "/net.npy"}, alpha={"npy": "alpha.npy"})
model("bad_absolute.json", points={"npy": os.path.join(outside, "net.npy")}, alpha={"npy": "alpha.npy"})
model("bad_reference.json", points={"npy": "net.npy", "mmap": True}, alpha={"npy": "alpha.npy"})
# Value rules an empty shard streams (tests ...EmptyShards...): alpha out of range; out of range
# early and NaN late (the NaN is the error); vertices that overflow fp64 (alpha tiny, net large).
late = al.copy(); late[2, 3] = 1.5
save("alpha_range.npy", late)
late[7, 1] = np.nan
save("alpha_nan_late.npy", late)
save("net_big.npy", P * 100)
model("bad_alpha_range.json", points={"npy": "net.npy"}, alpha={"npy": "alpha_range.npy"})
model("bad_alpha_nan_late.json", points={"npy": "net.npy"}, alpha={"npy": "alpha_nan_late.npy"})
model("bad_overflow.json", points={"npy": "net_big.npy"}, alpha=1e-308)
model("ref_uniform.json", points={"npy": "net.npy"}, alpha=0.5)
# Two faults at once: a NaN in the points and a bad alpha shape, or too few rows (the NaN is named).
model("bad_nan_alpha_shape.json", points={"npy": "nan.npy"}, alpha={"npy": "alpha_shape.npy"})
few = P[:1].copy(); few[0, 1, 1] = np.nan
save("nan_few.npy", few)
model("bad_nan_few_rows.json", points={"npy": "nan_few.npy"}, alpha=0.5)
# Nets a job on the CPU samples in bands as they stream (tests ...Bands...), each beside the same
# numbers written out: closed in u, α one number, a plain UBP net, a net beyond 2^200 in its last
# row (the CPU scales it: the job starts again whole), one with precision warnings.
model("ref_closed.json", points={"npy": "net.npy"}, alpha={"npy": "alpha.npy"}, closed=[True, False])
model("inline_closed.json", points=P.tolist(), alpha=al.tolist(), closed=[True, False])
model("inline_uniform.json", points=P.tolist(), alpha=0.5)
ubp = {"kind": "surface", "construction": "ubp", "order": 5, "lambda": 0.5, "closed": [True, True]}
json.dump(dict(ubp, points={"npy": "net.npy"}), open(os.path.join(d, "ref_ubp.json"), "w"))
json.dump(dict(ubp, points=P.tolist()), open(os.path.join(d, "inline_ubp.json"), "w"))
scaled = P.copy(); scaled[9] *= 1e70
save("net_scaled.npy", scaled)
model("ref_scaled.json", points={"npy": "net_scaled.npy"}, alpha={"npy": "alpha.npy"})
model("inline_scaled.json", points=scaled.tolist(), alpha=al.tolist())
risky = P + 1e13  # spans 9 units 1e13 from the origin (a coordinate beyond 1e150 would be scaled)
risky_alpha = al.copy(); risky_alpha[5, 5] = 1e-7
save("net_risky.npy", risky)
save("alpha_risky.npy", risky_alpha)
model("ref_risky.json", points={"npy": "net_risky.npy"}, alpha={"npy": "alpha_risky.npy"})
model("inline_risky.json", points=risky.tolist(), alpha=risky_alpha.tolist())
# For the fp32 kernels: a last row 1e7 times as far (the GPU scales the whole net by 2^-26, its
# first bands alone by 1), and a net that fp32 resolves poorly (1e6 from the origin, alpha 1e-3).
far = P.copy(); far[9] *= 1e7
save("net_far.npy", far)
model("ref_far.json", points={"npy": "net_far.npy"}, alpha={"npy": "alpha.npy"})
model("inline_far.json", points=far.tolist(), alpha=al.tolist())
coarse = P + 1e6
coarse_alpha = al.copy(); coarse_alpha[5, 5] = 1e-3
save("net_coarse.npy", coarse)
save("alpha_coarse.npy", coarse_alpha)
model("ref_coarse.json", points={"npy": "net_coarse.npy"}, alpha={"npy": "alpha_coarse.npy"})
model("inline_coarse.json", points=coarse.tolist(), alpha=coarse_alpha.tolist())
# Curves in files (tests ...Curves...), each beside the same numbers written out: α-EB open (2-D
# points, α a file), closed (3-D), closed with α one number, a closed UBP curve, an extended
# B-spline with span knots; and broken ones (a NaN late, α out of range, V beyond fp64, bad shapes,
# too few points).
mc = 40
tc = np.linspace(0, 5, mc)
C2 = np.stack([np.cos(tc) * (1 + 0.1 * tc), np.sin(1.3 * tc)], 1)
C3 = np.stack([np.cos(tc), np.sin(tc), 0.05 * tc * tc], 1)
ca = np.random.default_rng(4).uniform(0.1, 1.0, mc)
save("c2.npy", C2)
save("c3.npy", C3)
save("ca.npy", ca)
aebc = {"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": 0.25}
ubpc = {"kind": "curve", "construction": "ubp", "order": 5, "lambda": 0.5, "closed": True}
spans = [0.5 * s + 0.01 * s * s for s in range(mc - 2)]
ebsc = {"kind": "curve", "construction": "extended_bspline", "degree": 4, "knots": spans}
def curves(name, head, pts, file, alpha=None, alpha_file=None):
    ref = dict(head, points={"npy": file})
    written = dict(head, points=pts.tolist())
    if alpha is not None:
        ref["alpha"] = {"npy": alpha_file} if alpha_file else alpha
        written["alpha"] = alpha.tolist() if alpha_file else alpha
    json.dump(ref, open(os.path.join(d, "curve_ref_" + name + ".json"), "w"))
    json.dump(written, open(os.path.join(d, "curve_inline_" + name + ".json"), "w"))
curves("open", aebc, C2, "c2.npy", ca, "ca.npy")
curves("closed", dict(aebc, closed=True), C3, "c3.npy", ca, "ca.npy")
curves("uniform", dict(aebc, closed=True), C2, "c2.npy", 0.5)
curves("ubp", ubpc, C3, "c3.npy")
curves("knots", ebsc, C2, "c2.npy")
# For the fp32 kernels: a last point 1e7 times as far (the whole curve is scaled, its first bands
# not: the job starts again whole), and a curve fp32 resolves poorly (1e6 from the origin, α 1e-3).
far_curve = C2.copy(); far_curve[-1] *= 1e7
save("c_far.npy", far_curve)
curves("far", aebc, far_curve, "c_far.npy", ca, "ca.npy")
coarse_alpha_c = ca.copy(); coarse_alpha_c[7] = 1e-3
save("c_coarse.npy", C2 + 1e6)
save("ca_coarse.npy", coarse_alpha_c)
curves("coarse", aebc, C2 + 1e6, "c_coarse.npy", coarse_alpha_c, "ca_coarse.npy")
bad = C2.copy(); bad[30, 1] = np.nan
save("c_nan.npy", bad)
bad_alpha = ca.copy(); bad_alpha[12] = 1.5
save("ca_range.npy", bad_alpha)
save("c_big.npy", C2 * 1e300)
save("ca_short.npy", ca[:-1])
save("c_wide.npy", np.ones((mc, 4)))
save("c_few.npy", C2[:1])
def bad_curve(name, points, alpha):
    json.dump(dict(aebc, points={"npy": points}, alpha=alpha), open(os.path.join(d, "curve_bad_" + name + ".json"), "w"))
bad_curve("nan", "c_nan.npy", {"npy": "ca.npy"})
bad_curve("alpha_range", "c2.npy", {"npy": "ca_range.npy"})
bad_curve("overflow", "c_big.npy", 1e-300)
bad_curve("alpha_shape", "c2.npy", {"npy": "ca_short.npy"})
bad_curve("shape", "c_wide.npy", {"npy": "ca.npy"})
bad_curve("few", "c_few.npy", 0.5)
bad_curve("nan_alpha_shape", "c_nan.npy", {"npy": "ca_short.npy"})
# A rational B-spline surface from files.
save("wsurf.npy", np.random.default_rng(5).uniform(0.5, 2.0, (n, n)))
ku = [0, 0, 0] + list(np.linspace(0.1, 0.9, n - 3)) + [1, 1, 1]
json.dump({"kind": "surface", "construction": "bspline", "order": [3, 3], "knots": [ku, ku],
           "points": {"npy": "net.npy"}, "weights": {"npy": "wsurf.npy"}}, open(os.path.join(d, "nurbs_ref.json"), "w"))
)PY";

// Checks a model saved by --save-model against the JSON model it came from (argv: folder, source
// model, saved model relative to the folder).
constexpr const char* kCheckSaved = R"PY(
import json, os, sys
import numpy as np
folder, source, saved = sys.argv[1:4]
src = json.load(open(source))
path = os.path.join(folder, saved)
doc = json.load(open(path))
stem = os.path.basename(saved)[:-len(".json")]
for key in ("points", "alpha", "weights"):
    if key not in src:
        assert key not in doc, key
        continue
    want = np.asarray(src[key], dtype=float)
    if want.ndim == 0 or (want == want.flat[0]).all() and key == "alpha":
        assert doc[key] == want.flat[0], (key, doc[key])  # one number
        continue
    assert doc[key] == {"npy": stem + "." + key + ".npy"}, doc[key]
    got = np.load(os.path.join(os.path.dirname(path), doc[key]["npy"]))
    assert got.dtype == np.float64 and got.shape == want.shape and (got == want).all(), key
for key in src:
    if key not in ("points", "alpha", "weights"):
        assert doc[key] == src[key], (key, doc[key], src[key])
print("OK")
)PY";

// The warning lines of a command's stderr.
std::string warningLines(const std::string& err) {
  std::string out;
  for (size_t at = err.find("warning:"); at != std::string::npos; at = err.find("warning:", at + 1))
    out += err.substr(at, err.find('\n', at) - at) + "\n";
  return out;
}

class NpyArrays : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kPython) || std::system((std::string(kPython) + " -c 'import numpy' >/dev/null 2>&1").c_str()) != 0)
      GTEST_SKIP() << kPython << " with numpy is missing (scripts/setup.sh installs python3-numpy)";
    fs::create_directories(models());
    fs::create_directories(outside());
    writeText(dir_ / "make.py", kMakeArrays);
    writeText(dir_ / "check.py", kCheckSaved);
    ASSERT_EQ(std::system((std::string(kPython) + " " + quote((dir_ / "make.py").string()) + " " +
                           quote(models().string()) + " " + quote(outside().string()))
                              .c_str()),
              0);
  }
  fs::path models() const { return dir_ / "models"; }
  fs::path outside() const { return dir_ / "outside"; }

  CliResult sample(const std::string& model, const std::string& out, const std::string& extra = "") {
    return runCli("sample " + quote((models() / model).string()) + " -o " + quote((dir_ / out).string()) +
                      (model.rfind("curve", 0) == 0 ? " --samples 9" : " --grid 4") + " --derivatives --device cpu -q " +
                      extra,
                  dir_.path());
  }

  // The line of `key` in a sidecar ("" when it has none).
  std::string line(const std::string& sidecar, const std::string& key) const {
    const std::string text = readText(dir_ / sidecar);
    const size_t at = text.find("\"" + key + "\":");
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at) - at);
  }
  // The sidecar without the lines that name the model file, its digest and the output itself.
  std::string identity(const std::string& sidecar) const {
    std::string kept, text = readText(dir_ / sidecar);
    for (size_t at = 0; at < text.size();) {
      const size_t end = std::min(text.find('\n', at), text.size());
      const std::string line = text.substr(at, end - at);
      if (line.find("\"model_file\"") == std::string::npos && line.find("\"model_sha256\"") == std::string::npos &&
          line.find("\"source\"") == std::string::npos && line.find("\"data_file\"") == std::string::npos)
        kept += line + "\n";
      at = end + 1;
    }
    return kept;
  }

  // `ref` (its net in files, sampled in bands as it streams) and `written` (the same numbers in the
  // JSON, built whole) sampled with `options` to `format`: the same bytes, the same identity in the
  // sidecar (its metadata but for the model file and digest), the same precision warnings, and the
  // summary naming the bands.
  void expectBandsAsBuilt(const std::string& ref, const std::string& written, const std::string& format,
                          const std::string& options) {
    SCOPED_TRACE(ref + " to " + format);
    const std::string a = "banded" + format, b = "built" + format;
    const CliResult banded = runCli("sample " + quote((models() / ref).string()) + " -o " + quote((dir_ / a).string()) + options,
                                    dir_.path());
    const CliResult built = runCli(
        "sample " + quote((models() / written).string()) + " -o " + quote((dir_ / b).string()) + options, dir_.path());
    ASSERT_EQ(banded.rc, 0) << banded.err;
    ASSERT_EQ(built.rc, 0) << built.err;
    EXPECT_NE(banded.err.find("bands as they were sampled"), std::string::npos) << banded.err;
    EXPECT_EQ(built.err.find("bands"), std::string::npos) << built.err;
    EXPECT_GT(fs::file_size(dir_ / a), 1000u);
    EXPECT_TRUE(readText(dir_ / a) == readText(dir_ / b)) << "the bands sampled other bytes";
    EXPECT_EQ(warningLines(banded.err), warningLines(built.err));
    if (format == ".csv") return;
    EXPECT_EQ(identity(a + ".json"), identity(b + ".json"));
    const std::string ma = line(a + ".json", "metadata"), mb = line(b + ".json", "metadata");
    EXPECT_EQ(ma.substr(0, ma.find("\"model_file\"")), mb.substr(0, mb.find("\"model_file\""))) << "metadata";
  }

  // An empty shard written to empty.f64 and one that samples to one.f64: both written, the first
  // empty, and both with the same job fingerprint and metadata.
  void expectTheSameJob(const CliResult& empty, const CliResult& one) {
    ASSERT_EQ(empty.rc, 0) << empty.err;
    ASSERT_EQ(one.rc, 0) << one.err;
    EXPECT_EQ(fs::file_size(dir_ / "empty.f64"), 0u);
    EXPECT_GT(fs::file_size(dir_ / "one.f64"), 0u);
    for (const char* key : {"job", "metadata"}) {
      EXPECT_NE(line("empty.f64.json", key), "") << key;
      EXPECT_EQ(line("empty.f64.json", key), line("one.f64.json", key)) << key;
    }
  }

  ScratchDir dir_{"npy_arrays"};
};

TEST_F(NpyArrays, ReferencedArraysSampleExactlyAsTheSameNumbersInJson) {
  for (const auto& [inlineModel, refModel] : {std::pair{"inline.json", "ref.json"}, std::pair{"inline32.json", "ref32.json"},
                                              std::pair{"curve_inline.json", "curve_ref.json"}}) {
    SCOPED_TRACE(refModel);
    const CliResult a = sample(inlineModel, "a.f64"), b = sample(refModel, "b.f64");
    ASSERT_EQ(a.rc, 0) << a.err;
    ASSERT_EQ(b.rc, 0) << b.err;
    const std::string inlineBytes = readText(dir_ / "a.f64"), refBytes = readText(dir_ / "b.f64");
    EXPECT_GT(inlineBytes.size(), 1000u);
    EXPECT_TRUE(inlineBytes == refBytes) << "the referenced arrays sample to other bytes";
  }
}

TEST_F(NpyArrays, BadArraysNameTheKeyAndTheFileAndWriteNothing) {
  struct Case {
    const char* model;
    const char* key;
    const char* file;
    const char* rule;  // a piece of the message
  };
  const Case cases[] = {
      {"bad_int.json", "points", "int.npy", "not float64 or float32"},
      {"bad_big_endian.json", "points", "big_endian.npy", "little-endian"},
      {"bad_fortran.json", "points", "fortran.npy", "Fortran order"},
      {"bad_shape.json", "points", "shape.npy", "(rows, cols, 3)"},
      {"bad_nan.json", "points[3][4][1]", "nan.npy", "finite"},
      {"bad_truncated.json", "points", "truncated.npy", "truncated"},
      {"bad_huge.json", "points", "huge.npy", "data bytes"},
      {"bad_link.json", "points", "link.npy", "outside the folder of the model file"},
      {"bad_dotdot.json", "points", "net.npy", "outside the folder of the model file"},
      {"bad_absolute.json", "points", "net.npy", "absolute path"},
      {"bad_missing.json", "points", "missing.npy", "cannot open"},
      {"bad_alpha_shape.json", "alpha", "alpha_shape.npy", "shape (10, 10)"},
      {"bad_reference.json", "points", "mmap", "{\"npy\": \"FILE.npy\"}"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.model);
    const CliResult r = sample(c.model, "out.f64");
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find(std::string("error: ") + c.key + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.file), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.rule), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.f64")) << "partial output";
  }
  // The user may allow arrays outside the folder.
  for (const char* model : {"bad_link.json", "bad_dotdot.json", "bad_absolute.json"}) {
    const CliResult r = sample(model, "out.f64", "--allow-outside-arrays");
    EXPECT_EQ(r.rc, 0) << model << ": " << r.err;
  }
}

// --save-model writes the model with its arrays as .npy files beside it, committed with the
// samples: numpy reads back the values of the JSON model, a uniform α stays a number, and the
// saved model samples to the same bytes. Bad names are refused before anything is written.

TEST_F(NpyArrays, SaveModelWritesTheNetAsArrays) {
  writeText(models() / "curve_uniform.json",
            R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": 0.5, "closed": true,
                "points": [[0, 0], [2, 1], [3, 3], [1, 4], [-1, 2]], "alpha": 0.75})");
  fs::create_directories(dir_ / "saved");
  for (const std::string model : {"inline.json", "curve_inline.json", "curve_uniform.json"}) {
    SCOPED_TRACE(model);
    const std::string saved = "saved/" + model;
    const CliResult r = sample(model, "a.f64", "--save-model " + quote((dir_ / saved).string()));
    ASSERT_EQ(r.rc, 0) << r.err;
    const CliResult check = runCaptured(std::string(kPython) + " " + quote((dir_ / "check.py").string()) + " " +
                                            quote(dir_.path().string()) + " " + quote((models() / model).string()) +
                                            " " + quote(saved) + " >" + quote((dir_ / "check.out").string()) + " 2>" +
                                            quote((dir_ / "check.err").string()),
                                        dir_ / "check.out", dir_ / "check.err");
    EXPECT_EQ(check.rc, 0) << check.err;
    EXPECT_NE(check.out.find("OK"), std::string::npos) << check.out;
    // The saved model samples to the same bytes (from its own folder, with its arrays).
    const CliResult again =
        runCli("sample " + quote((dir_ / saved).string()) + " -o " + quote((dir_ / "b.f64").string()) +
                   (model.rfind("curve", 0) == 0 ? " --samples 9" : " --grid 4") + " --derivatives --device cpu -q",
               dir_.path());
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_TRUE(readText(dir_ / "a.f64") == readText(dir_ / "b.f64")) << "the saved model samples otherwise";
  }
  const std::string uniform = readText(dir_ / "saved/curve_uniform.json");
  EXPECT_NE(uniform.find("\"alpha\": 0.75"), std::string::npos) << uniform;
  EXPECT_FALSE(fs::exists(dir_ / "saved/curve_uniform.alpha.npy"));

  // Refused before anything is written: not .json, the model itself, a file the model reads.
  const std::string notJson = quote((dir_ / "m.txt").string());
  const CliResult r1 = sample("inline.json", "out.f64", "--save-model " + notJson);
  EXPECT_EQ(r1.rc, 2);
  EXPECT_NE(r1.err.find("--save-model: must name a model file ending in .json"), std::string::npos) << r1.err;
  const CliResult r2 = sample("ref.json", "out.f64", "--save-model " + quote((models() / "ref.json").string()));
  EXPECT_EQ(r2.rc, 2);
  EXPECT_NE(r2.err.find("is the same file as MODEL"), std::string::npos) << r2.err;
  // "net.json" would write net.points.npy; a model that reads net.points.npy must not lose it.
  fs::copy_file(models() / "net.npy", models() / "net.points.npy");
  writeText(models() / "reads_points.json",
            R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "points": {"npy": "net.points.npy"}, "alpha": 0.5})");
  const CliResult r3 = sample("reads_points.json", "out.f64", "--save-model " + quote((models() / "net.json").string()));
  EXPECT_EQ(r3.rc, 2);
  EXPECT_NE(r3.err.find("which this command reads"), std::string::npos) << r3.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.f64")) << "partial output";
  EXPECT_FALSE(fs::exists(models() / "net.json")) << "partial output";
}

// The job metadata's model_sha256 covers the arrays too (the JSON alone stays the same), and merge
// refuses shards sampled before and after an array changed; shards of the same arrays merge to the
// unsharded file.
TEST_F(NpyArrays, ShardsOfChangedArraysDoNotMerge) {
  const std::string model = quote((models() / "ref.json").string());
  auto shard = [&](int k) {
    return runCli("sample " + model + " -o " + quote((dir_ / ("s" + std::to_string(k) + ".f64")).string()) +
                      " --grid 4 --device cpu -q --shard " + std::to_string(k) + "/2",
                  dir_.path());
  };
  ASSERT_EQ(shard(1).rc, 0);
  ASSERT_EQ(shard(2).rc, 0);
  const std::string mergeArgs = "merge -o " + quote((dir_ / "whole.f64").string()) + " " +
                                quote((dir_ / "s1.f64").string()) + " " + quote((dir_ / "s2.f64").string());
  const CliResult same = runCli(mergeArgs, dir_.path());
  ASSERT_EQ(same.rc, 0) << same.err;
  const CliResult whole = runCli("sample " + model + " -o " + quote((dir_ / "one.f64").string()) + " --grid 4 --device cpu -q",
                                 dir_.path());
  ASSERT_EQ(whole.rc, 0) << whole.err;
  EXPECT_TRUE(readText(dir_ / "whole.f64") == readText(dir_ / "one.f64"));

  // The same JSON, another net: shard 2 again from the changed array.
  fs::copy_file(models() / "net32.npy", models() / "net.npy", fs::copy_options::overwrite_existing);
  writeText(models() / "ref.json", readText(models() / "ref.json"));  // the JSON bytes stay the same
  const auto sha = [&](const std::string& sidecar) {
    const std::string text = readText(dir_ / sidecar), key = "\"model_sha256\":\"";
    const size_t at = text.find(key);
    return at == std::string::npos ? std::string() : text.substr(at + key.size(), 64);
  };
  const std::string before = sha("s2.f64.json");
  ASSERT_EQ(before.size(), 64u);
  ASSERT_EQ(shard(2).rc, 0);
  EXPECT_NE(sha("s2.f64.json"), before) << "model_sha256 does not see the changed array";
  fs::remove(dir_ / "whole.f64");
  const CliResult changed = runCli(mergeArgs, dir_.path());
  EXPECT_EQ(changed.rc, 2) << changed.err;
  EXPECT_NE(changed.err.find("belongs to another job"), std::string::npos) << changed.err;  // its id hashes model_sha256
}

// A shard with no items streams its net's files through the rules and the fingerprint without
// holding them (io/streamed_net.h): it carries the job fingerprint and metadata of the shards that
// sample, so that merge takes it, and the shards merge into the unsharded job's bytes.
TEST_F(NpyArrays, EmptyShardsCarryTheJobOfTheShardsThatSample) {
  auto shard = [&](const std::string& model, int k, int n, const std::string& out) {
    return runCli("sample " + quote((models() / model).string()) + " -o " + quote((dir_ / out).string()) +
                      " --grid 4 --device cpu -q --shard " + std::to_string(k) + "/" + std::to_string(n),
                  dir_.path());
  };
  // 81 patches (α-EB) or 64 (the rational B-spline) in 100 shards: shard 1 has none, shard 100 one.
  for (const char* model : {"ref.json", "ref32.json", "ref_uniform.json", "nurbs_ref.json"}) {
    SCOPED_TRACE(model);
    const CliResult empty = shard(model, 1, 100, "empty.f64"), one = shard(model, 100, 100, "one.f64");
    expectTheSameJob(empty, one);
  }
  // 82 shards of 81 patches: shard 1 is empty; all of them merge into the whole job's file.
  std::string files;
  for (int k = 1; k <= 82; ++k) {
    const std::string out = "s" + std::to_string(k) + ".f64";
    const CliResult r = shard("ref.json", k, 82, out);
    ASSERT_EQ(r.rc, 0) << k << ": " << r.err;
    files += " " + quote((dir_ / out).string());
  }
  EXPECT_EQ(fs::file_size(dir_ / "s1.f64"), 0u);
  const CliResult merged = runCli("merge -o " + quote((dir_ / "merged.f64").string()) + files, dir_.path());
  ASSERT_EQ(merged.rc, 0) << merged.err;
  const CliResult whole = runCli("sample " + quote((models() / "ref.json").string()) + " -o " +
                                     quote((dir_ / "whole.f64").string()) + " --grid 4 --device cpu -q",
                                 dir_.path());
  ASSERT_EQ(whole.rc, 0) << whole.err;
  EXPECT_TRUE(readText(dir_ / "merged.f64") == readText(dir_ / "whole.f64"));
}

// A shard with no items refuses a bad net with the error (and exit 2, and no output) of the
// unsharded job, which reads the model whole: the rules it streams, and those it leaves to the
// built surface (overflowing vertices), in the same order, also when a net breaks two rules.
TEST_F(NpyArrays, EmptyShardsRefuseBadArraysAsTheWholeJob) {
  for (const char* model :
       {"bad_nan.json", "bad_alpha_range.json", "bad_alpha_nan_late.json", "bad_overflow.json", "bad_shape.json",
        "bad_alpha_shape.json", "bad_truncated.json", "bad_huge.json", "bad_link.json", "bad_int.json",
        "bad_nan_alpha_shape.json", "bad_nan_few_rows.json"}) {
    SCOPED_TRACE(model);
    std::string errors[2];
    for (const std::string shard : {" --shard 1/200", ""}) {
      const CliResult r = runCli("sample " + quote((models() / model).string()) + " -o " +
                                     quote((dir_ / "out.f64").string()) + " --grid 4 --device cpu -q" + shard,
                                 dir_.path());
      EXPECT_EQ(r.rc, 2) << shard << ": " << r.err;
      EXPECT_FALSE(fs::exists(dir_ / "out.f64")) << shard << ": partial output";
      errors[shard.empty() ? 1 : 0] = r.err;
    }
    EXPECT_NE(errors[0], "");
    EXPECT_EQ(errors[0], errors[1]);
  }
}

// A job on the CPU to a raw, .npy or CSV file samples a net in files in bands of patch rows as it
// reads them (io/streamed_bands.h): the same bytes as the net written out in JSON, the same job
// fingerprint and metadata in the sidecar, for closed and open nets, α per vertex or one number,
// plain families, and shards that sample; the summary says how many bands it took.
TEST_F(NpyArrays, JobsOnTheCpuSampleTheNetInBandsAsItStreams) {
  const std::pair<const char*, const char*> pairs[] = {
      {"ref.json", "inline.json"},           {"ref32.json", "inline32.json"},
      {"ref_closed.json", "inline_closed.json"}, {"ref_uniform.json", "inline_uniform.json"},
      {"ref_ubp.json", "inline_ubp.json"}};
  for (const auto& [ref, written] : pairs) {
    for (const char* format : {".f32", ".f64", ".npy", ".csv"})
      expectBandsAsBuilt(ref, written, format, " --grid 3x4 --derivatives --normals --device cpu");
  }
  // Shards that sample stream their own rows' bands; they merge into the whole job's bytes.
  std::string files;
  for (int k = 1; k <= 3; ++k) {
    const std::string out = "part" + std::to_string(k) + ".f64";
    const CliResult r = runCli("sample " + quote((models() / "ref_closed.json").string()) + " -o " +
                                   quote((dir_ / out).string()) + " --grid 4 --device cpu --shard " + std::to_string(k) + "/3",
                               dir_.path());
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("bands as they were sampled"), std::string::npos) << r.err;
    files += " " + quote((dir_ / out).string());
  }
  ASSERT_EQ(runCli("merge -o " + quote((dir_ / "merged.f64").string()) + files, dir_.path()).rc, 0);
  ASSERT_EQ(runCli("sample " + quote((models() / "inline_closed.json").string()) + " -o " +
                       quote((dir_ / "whole.f64").string()) + " --grid 4 --device cpu -q",
                   dir_.path())
                .rc,
            0);
  EXPECT_GT(fs::file_size(dir_ / "whole.f64"), 1000u);
  EXPECT_TRUE(readText(dir_ / "merged.f64") == readText(dir_ / "whole.f64"));
}

// A curve whose points (and α) are files streams the same way, in bands of spans
// (io/streamed_bands.h streamCurveSpans): a job to a raw, .npy or CSV file samples the bytes of the
// same curve written out, with the same identity in the sidecar (open and closed α-EB curves,
// whose wrapped spans need the first points at the end; α one number; a closed UBP curve; span
// knots); shards that sample merge into the whole job's bytes, and an empty shard carries the job
// of the shards that sample.
TEST_F(NpyArrays, CurvesInFilesSampleInBandsAsTheyStream) {
  auto run = [&](const std::string& model, const std::string& out, const std::string& extra = "") {
    return runCli("sample " + quote((models() / model).string()) + " -o " + quote((dir_ / out).string()) +
                      " --samples 5 --derivatives --device cpu" + extra,
                  dir_.path());
  };
  for (const char* name : {"open", "closed", "uniform", "ubp", "knots", "far", "coarse"}) {
    const std::string ref = std::string("curve_ref_") + name + ".json", written = std::string("curve_inline_") + name + ".json";
    for (const char* format : {".f32", ".f64", ".npy", ".csv"})
      expectBandsAsBuilt(ref, written, format, " --samples 5 --derivatives --device cpu");
  }
  // Three shards of the closed curve (the first and last hold its wrapped spans) merge into the
  // whole job's bytes; an empty shard of 100 carries the job and metadata of one that samples.
  std::string files;
  for (int k = 1; k <= 3; ++k) {
    const std::string out = "part" + std::to_string(k) + ".f64";
    const CliResult r = run("curve_ref_closed.json", out, " --shard " + std::to_string(k) + "/3");
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("bands as they were sampled"), std::string::npos) << r.err;
    files += " " + quote((dir_ / out).string());
  }
  ASSERT_EQ(runCli("merge -o " + quote((dir_ / "merged.f64").string()) + files, dir_.path()).rc, 0);
  ASSERT_EQ(run("curve_inline_closed.json", "whole.f64").rc, 0);
  EXPECT_GT(fs::file_size(dir_ / "whole.f64"), 1000u);
  EXPECT_TRUE(readText(dir_ / "merged.f64") == readText(dir_ / "whole.f64"));
  for (const char* model : {"curve_ref_closed.json", "curve_ref_uniform.json", "curve_ref_knots.json"}) {
    SCOPED_TRACE(model);
    const CliResult empty = run(model, "empty.f64", " --shard 1/100"), one = run(model, "one.f64", " --shard 100/100");
    expectTheSameJob(empty, one);
  }
}

// A curve in files that breaks a rule is refused by an empty shard and by the whole job (which
// streams it in bands) as the job that reads it whole refuses it: the same error, exit 2, no file.
TEST_F(NpyArrays, CurvesInFilesRefuseBadArraysAsTheWholeJob) {
  for (const char* model : {"curve_bad_nan.json", "curve_bad_alpha_range.json", "curve_bad_overflow.json",
                            "curve_bad_alpha_shape.json", "curve_bad_shape.json", "curve_bad_few.json",
                            "curve_bad_nan_alpha_shape.json"}) {
    SCOPED_TRACE(model);
    std::string errors[3];
    int k = 0;
    const std::string saveModel = " --save-model " + quote((dir_ / "saved.json").string());
    for (const std::string& extra : {std::string(" --shard 1/200"), std::string(), saveModel}) {
      fs::remove(dir_ / "out.f32");
      const CliResult r = runCli("sample " + quote((models() / model).string()) + " -o " +
                                     quote((dir_ / "out.f32").string()) + " --samples 4 --device cpu -q" + extra,
                                 dir_.path());
      EXPECT_EQ(r.rc, 2) << extra << ": " << r.err;
      EXPECT_FALSE(fs::exists(dir_ / "out.f32")) << extra << ": partial output";
      errors[k++] = r.err;
    }
    EXPECT_NE(errors[2], "");
    EXPECT_EQ(errors[0], errors[2]) << "an empty shard";
    EXPECT_EQ(errors[1], errors[2]) << "the whole job";
  }
}

// What the bands cannot settle alone starts the job again whole, whose outcome is then the job's:
// a net the CPU scales (beyond 2^200, here in its last row) samples to the bytes of the same net
// written out, and its summary names no bands; the precision warnings, which need every value,
// come after the samples and are the built net's. A write that fails is not tried again.
TEST_F(NpyArrays, BandedJobsEndAsTheWholeJob) {
  const CliResult scaled = runCli("sample " + quote((models() / "ref_scaled.json").string()) + " -o " +
                                      quote((dir_ / "a.f64").string()) + " --grid 4 --derivatives --device cpu",
                                  dir_.path());
  ASSERT_EQ(scaled.rc, 0) << scaled.err;
  EXPECT_EQ(scaled.err.find("bands"), std::string::npos) << scaled.err;
  ASSERT_EQ(sample("inline_scaled.json", "b.f64").rc, 0);
  EXPECT_TRUE(readText(dir_ / "a.f64") == readText(dir_ / "b.f64"));

  auto warnings = [](const std::string& err) {
    std::string out;
    for (size_t at = err.find("warning:"); at != std::string::npos; at = err.find("warning:", at + 1))
      out += err.substr(at, err.find('\n', at) - at) + "\n";
    return out;
  };
  const CliResult risky = runCli("sample " + quote((models() / "ref_risky.json").string()) + " -o " +
                                     quote((dir_ / "c.f64").string()) + " --grid 4 --device cpu",
                                 dir_.path());
  const CliResult written = runCli("sample " + quote((models() / "inline_risky.json").string()) + " -o " +
                                       quote((dir_ / "d.f64").string()) + " --grid 4 --device cpu",
                                   dir_.path());
  ASSERT_EQ(risky.rc, 0) << risky.err;
  ASSERT_EQ(written.rc, 0) << written.err;
  EXPECT_NE(risky.err.find("bands as they were sampled"), std::string::npos) << risky.err;
  EXPECT_NE(warnings(risky.err).find("from the origin"), std::string::npos) << risky.err;
  EXPECT_NE(warnings(risky.err).find("alpha[5][5]"), std::string::npos) << risky.err;
  EXPECT_EQ(warnings(risky.err), warnings(written.err));

  // A write that fails (a 64 KiB file size limit against 48 MB of records) ends the job: exit 3,
  // the file system's message, nothing left.
  fs::create_directories(dir_ / "limited");
  const CliResult full = runShell("bash -c 'ulimit -f 64; exec \"$0\" \"$@\"' " + quote(SHAPESPLINE_CLI) +
                                      " sample " + quote((models() / "ref.json").string()) + " -o " +
                                      quote((dir_ / "limited" / "e.f64").string()) +
                                      " --grid 64 --derivatives --device cpu -q",
                                  dir_.path());
  EXPECT_EQ(full.rc, 3) << full.err;
  EXPECT_NE(full.err.find("File too large"), std::string::npos) << full.err;
  EXPECT_TRUE(fs::is_empty(dir_ / "limited")) << "partial output";
}

// The same on the GPU (fp32 kernels): bands planned as the whole net is, the bytes of the net
// written out; a net whose whole scale differs from its first bands' starts again whole; the fp32
// warnings after the samples are the built net's.
TEST_F(NpyArrays, JobsOnVulkanSampleTheNetInBandsToo) {
  REQUIRE_VULKAN();
  auto run = [&](const std::string& model, const std::string& out) {
    return runCli("sample " + quote((models() / model).string()) + " -o " + quote((dir_ / out).string()) +
                      " --grid 3x4 --normals --device vulkan --precision float --require-device",
                  dir_.path());
  };
  for (const auto& [ref, written] :
       {std::pair{"ref.json", "inline.json"}, std::pair{"ref_closed.json", "inline_closed.json"},
        std::pair{"ref_ubp.json", "inline_ubp.json"}, std::pair{"ref_far.json", "inline_far.json"},
        std::pair{"ref_coarse.json", "inline_coarse.json"}}) {
    SCOPED_TRACE(ref);
    const CliResult banded = run(ref, "a.f32"), built = run(written, "b.f32");
    ASSERT_EQ(banded.rc, 0) << banded.err;
    ASSERT_EQ(built.rc, 0) << built.err;
    const bool restarts = std::string(ref) == "ref_far.json";
    EXPECT_EQ(banded.err.find("bands as they were sampled") == std::string::npos, restarts) << banded.err;
    EXPECT_GT(fs::file_size(dir_ / "a.f32"), 1000u);
    EXPECT_TRUE(readText(dir_ / "a.f32") == readText(dir_ / "b.f32")) << "the bands sampled other bytes";
    EXPECT_EQ(warningLines(banded.err), warningLines(built.err));
    if (std::string(ref) == "ref_coarse.json") {
      EXPECT_NE(warningLines(banded.err).find("fp32 GPU kernels lose"), std::string::npos) << banded.err;
      EXPECT_NE(warningLines(banded.err).find("in fp32 (7 digits)"), std::string::npos) << banded.err;
    }
  }
}

// Curves in files on the GPU (fp32 kernels): bands of spans planned as the whole curve is, the
// bytes, identity and precision warnings of the curve written out; a curve whose whole scale
// differs from its first bands' starts again whole.
TEST_F(NpyArrays, CurvesInFilesSampleInBandsOnVulkanToo) {
  REQUIRE_VULKAN();
  const std::string options = " --samples 5 --derivatives --device vulkan --precision float --require-device";
  for (const char* name : {"open", "closed", "uniform", "ubp", "knots", "coarse"}) {
    const std::string ref = std::string("curve_ref_") + name + ".json", written = std::string("curve_inline_") + name + ".json";
    expectBandsAsBuilt(ref, written, ".f32", options);
  }
  const CliResult coarse = runCli("sample " + quote((models() / "curve_ref_coarse.json").string()) + " -o " +
                                      quote((dir_ / "coarse.f32").string()) + options, dir_.path());
  EXPECT_NE(warningLines(coarse.err).find("fp32 GPU kernels lose"), std::string::npos) << coarse.err;
  const CliResult far = runCli("sample " + quote((models() / "curve_ref_far.json").string()) + " -o " +
                                   quote((dir_ / "far_a.f32").string()) + options, dir_.path());
  const CliResult farBuilt = runCli("sample " + quote((models() / "curve_inline_far.json").string()) + " -o " +
                                        quote((dir_ / "far_b.f32").string()) + options, dir_.path());
  ASSERT_EQ(far.rc, 0) << far.err;
  ASSERT_EQ(farBuilt.rc, 0) << farBuilt.err;
  EXPECT_EQ(far.err.find("bands"), std::string::npos) << "the scaled curve was not started again whole: " << far.err;
  EXPECT_TRUE(readText(dir_ / "far_a.f32") == readText(dir_ / "far_b.f32"));
}

}  // namespace
}  // namespace shapespline::test
