// io/streamed_net.h and the pieces it is made of (issue 31: a shard with no items of a net in files
// runs in bounded memory). What a stream gives must be what the built surface gives: the same job
// fingerprint (FingerprintWords / SurfaceFingerprint fed in runs of any length), the same α in the
// metadata (AlphaTally), and, for a broken net, the same first error as the full parse names.
// io/streamed_bands.h streams the same values and hands out bands of patch rows on the way: each
// must be the whole surface's patchRows, and the stream's identity the built surface's.
#include <shapespline/io/streamed_net.h>
#include <shapespline/io/streamed_bands.h>

#include <shapespline/core/surface.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/npy_array.h>
#include <shapespline/io/shard_info.h>

#include "support/test_models.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace shapespline::io {
namespace {

namespace fs = std::filesystem;

// ---- Pieces: the same hash, the same α summary, the same values -----------------------------------

TEST(FingerprintWords, PiecesHashAsTheWholeSequence) {
  std::mt19937_64 rng(7);
  std::vector<uint64_t> words(23);
  for (uint64_t& w : words) w = rng();
  const auto* bytes = reinterpret_cast<const unsigned char*>(words.data());
  for (size_t n = 0; n <= words.size(); ++n) {
    FingerprintWords whole;
    whole.begin(12345);
    whole.add(bytes, n);
    const uint64_t expected = whole.end(12345);
    // Every split into three pieces (the middle one possibly empty) gives the whole's hash.
    for (size_t a = 0; a <= n; ++a)
      for (size_t b = a; b <= n; ++b) {
        FingerprintWords parts;
        parts.begin(12345);
        parts.add(bytes, a);
        parts.add(bytes + 8 * a, b - a);
        parts.add(bytes + 8 * b, n - b);
        ASSERT_EQ(parts.end(12345), expected) << n << " words split at " << a << ", " << b;
      }
  }
  // And the hash depends on every word: changing one of 23 changes it.
  FingerprintWords a, b;
  a.begin(1), b.begin(1);
  a.add(bytes, words.size());
  words[22] ^= 1;
  b.add(bytes, words.size());
  EXPECT_NE(a.end(1), b.end(1));
}

SampleLayout gridLayout(const Surface& s) {
  SampleLayout l;
  l.surface = true;
  l.samplesU = l.samplesV = 4;
  l.fields = fieldBit(Field::Point);
  l.totalItems = static_cast<size_t>(s.patches().u.last - s.patches().u.first + 1) *
                 static_cast<size_t>(s.patches().v.last - s.patches().v.first + 1);
  return l;
}

// The fingerprint of `model` streamed `run` values at a time.
std::string streamedFingerprint(const SurfaceModel& model, const SampleLayout& layout, size_t run) {
  SurfaceFingerprint f(model, model.alpha.size(), model.weights.size(), layout, OutputFormat::RawF32);
  for (size_t k = 0; k < model.points.size(); k += run)
    f.points(model.points.data() + k, std::min(run, model.points.size() - k));
  for (size_t k = 0; k < model.alpha.size(); k += run)
    f.alphas(model.alpha.data() + k, std::min(run, model.alpha.size() - k));
  for (size_t k = 0; k < model.weights.size(); k += run)
    f.weights(model.weights.data() + k, std::min(run, model.weights.size() - k));
  return f.finish();
}

TEST(SurfaceFingerprint, StreamedInRunsEqualsTheBuiltSurfaces) {
  FamilySpec aeb;
  aeb.construction = Construction::AlphaEB;
  aeb.degree = 5;
  FamilySpec ubp;
  ubp.construction = Construction::UBP;
  ubp.order = 4;
  for (const SurfaceModel& model : {test::wavyNet(aeb, 9, true), test::wavyNet(ubp, 7, false),
                                    test::nurbsTorus(3.0, 1.0), test::alphaEBTube(6, 5)}) {
    const Surface s = Surface::create(model);
    const SampleLayout layout = gridLayout(s);
    const std::string built = jobFingerprint(s, layout, OutputFormat::RawF32);
    // Runs that end inside rows, at row ends, a whole row and more, everything at once.
    const size_t cols = static_cast<size_t>(model.cols);
    for (size_t run : {size_t{1}, size_t{2}, size_t{3}, size_t{5}, cols, cols + 1, size_t{1000}})
      EXPECT_EQ(streamedFingerprint(model, layout, run), built) << "runs of " << run;
    SurfaceModel other = model;
    other.points.back().z = std::nextafter(other.points.back().z, 10.0);
    EXPECT_NE(streamedFingerprint(other, layout, 3), built) << "the last coordinate does not enter the fingerprint";
  }
}

TEST(AlphaTally, RunsKeepWhatSetAlphaKeeps) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> alpha(0.05, 1.0);
  for (size_t n :
       {size_t{0}, size_t{1}, size_t{100}, size_t{kMetadataAlphaListMax}, size_t{kMetadataAlphaListMax + 1}}) {
    std::vector<double> values(n);
    for (size_t k = 0; k < n; ++k) values[k] = k % 7 == 0 ? 1.0 : alpha(rng);
    JobMetadata whole;
    whole.setAlpha(values, 1, static_cast<int>(n));
    AlphaTally tally;
    for (size_t k = 0; k < n; k += 33) tally.add(values.data() + k, std::min<size_t>(33, n - k));
    JobMetadata runs;
    runs.setAlpha(tally, 1, static_cast<int>(n));
    EXPECT_EQ(runs.alphaSummary, whole.alphaSummary) << n;
    EXPECT_EQ(runs.alpha, whole.alpha) << n;
    EXPECT_EQ(runs.alpha.empty(), n == 0 || n > kMetadataAlphaListMax) << n;
  }
}

// ---- Files: a net in .npy files -------------------------------------------------------------------

// A C-order little-endian .npy file (format 1) of `values` in `shape`, float64 or float32.
std::string npyBytes(const std::string& shape, const std::vector<double>& values, bool float64 = true) {
  std::string dict = std::string("{'descr': '") + (float64 ? "<f8" : "<f4") + "', 'fortran_order': False, 'shape': " +
                     shape + ", }";
  while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string out = "\x93NUMPY";
  out += char(1);
  out += char(0);
  out += char(dict.size() & 0xff);
  out += char(dict.size() >> 8);
  out += dict;
  for (double v : values) {
    if (float64) {
      out.append(reinterpret_cast<const char*>(&v), 8);
    } else {
      const float f = static_cast<float>(v);
      out.append(reinterpret_cast<const char*>(&f), 4);
    }
  }
  return out;
}

// The model of `torus` (a rational bspline surface) with its points and weights in these files;
// without a weights file, its weights written out as rows.
std::string torusDoc(const SurfaceModel& torus, const std::string& points, const std::string& weights) {
  nlohmann::json doc = {{"kind", "surface"}, {"construction", "bspline"}, {"order", {3, 3}},
                        {"knots", {torus.knotsU, torus.knotsV}}};
  doc["points"] = {{"npy", points}};
  if (!weights.empty()) {
    doc["weights"] = {{"npy", weights}};
  } else {
    doc["weights"] = nlohmann::json::array();
    for (int i = 0; i < torus.rows; ++i)
      doc["weights"].push_back(std::vector<double>(torus.weights.begin() + i * torus.cols,
                                                   torus.weights.begin() + (i + 1) * torus.cols));
  }
  return doc.dump();
}

std::vector<double> flat(const std::vector<glm::dvec3>& points) {
  return std::vector<double>(&points.data()->x, &points.data()->x + 3 * points.size());
}

class StreamedNet : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("shapespline_streamed_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
  }

  // `doc` (a model naming files in dir_) as the full parse sees it: its error, or "" and `built`.
  std::string fullParse(const std::string& doc, std::optional<Surface>& built) {
    write("m.json", doc);
    try {
      built.emplace(Surface::create(std::get<SurfaceModel>(loadModelFile(dir_ / "m.json"))));
      return "";
    } catch (const ModelError& e) {
      return e.what();
    }
  }
  // The same as an outline whose values are streamed `window` points at a time: its error, or ""
  // with `net` and the fingerprint for `layout`.
  std::string streamed(const std::string& doc, size_t window, const SampleLayout& layout, io::StreamedNet& net,
                       std::string& fingerprint) {
    write("m.json", doc);
    ModelArrays arrays;
    try {
      const SurfaceModel outline = outlineOf(doc, arrays);
      EXPECT_FALSE(arrays.deferred.empty());
      EXPECT_TRUE(outline.points.empty()) << "an outline read its points";
      SurfaceFingerprint f = fingerprintFor(outline, arrays, layout);
      net = streamSurfaceNet(outline, arrays, f, window);
      fingerprint = f.finish();
      return "";
    } catch (const ModelError& e) {
      return e.what();
    }
  }

  // `doc` parsed as an outline (its array files in dir_, left unread), and the job fingerprint for it.
  SurfaceModel outlineOf(const std::string& doc, ModelArrays& arrays) {
    arrays.folder = dir_;
    arrays.outline = true;
    return std::get<SurfaceModel>(parseModelText(doc, &arrays));
  }
  static SurfaceFingerprint fingerprintFor(const SurfaceModel& outline, const ModelArrays& arrays,
                                           const SampleLayout& layout) {
    const SurfaceCounts counts = outlineCounts(outline, arrays);
    return SurfaceFingerprint(outline, counts.alpha, counts.weights, layout, OutputFormat::RawF32);
  }

  fs::path dir_;
};

// Valid nets: the stream's fingerprint, α, magnitude and rational flag are the built surface's, for
// windows that cut rows anywhere; the outline holds no values.
TEST_F(StreamedNet, GivesTheBuiltSurfacesFingerprintAndMetadata) {
  FamilySpec aeb;
  aeb.construction = Construction::AlphaEB;
  aeb.degree = 5;
  const SurfaceModel wavy = test::wavyNet(aeb, 9, true, 3.0);
  write("net.npy", npyBytes("(9, 9, 3)", flat(wavy.points)));
  write("alpha.npy", npyBytes("(9, 9)", wavy.alpha));
  const SurfaceModel torus = test::nurbsTorus(3.0, 1.0);
  write("torus.npy", npyBytes("(9, 9, 3)", flat(torus.points)));
  write("w.npy", npyBytes("(9, 9)", torus.weights, false));  // float32 weights
  const std::vector<std::string> docs = {
      R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": {"npy": "alpha.npy"}, )"
      R"("points": {"npy": "net.npy"}})",
      R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 0.25, "points": {"npy": "net.npy"}})",
      R"({"kind": "surface", "construction": "extended_bspline", "degree": 4, "closed": [true, false], )"
      R"("points": {"npy": "net.npy"}})",
      torusDoc(torus, "torus.npy", "w.npy"),
      torusDoc(torus, "torus.npy", ""),
  };
  for (const std::string& doc : docs) {
    SCOPED_TRACE(doc);
    std::optional<Surface> built;
    ASSERT_EQ(fullParse(doc, built), "");
    const SampleLayout layout = gridLayout(*built);
    const JobMetadata full = jobMetadataOf(*built, "m.json", "", "cpu", Precision::Double, Precision::Double, 4, 4);
    for (size_t window : {size_t{1}, size_t{7}, size_t{9}, size_t{kStreamWindowPoints}}) {
      io::StreamedNet net;
      std::string fingerprint;
      ASSERT_EQ(streamed(doc, window, layout, net, fingerprint), "") << window;
      EXPECT_EQ(fingerprint, jobFingerprint(*built, layout, OutputFormat::RawF32)) << window;
      const JobMetadata m = jobMetadataOf(built->model(), net.alpha, net.rational, "m.json", "", "cpu",
                                          Precision::Double, Precision::Double, 4, 4);
      EXPECT_EQ(metadataJson(m), metadataJson(full)) << window;
      double largest = 0.0;
      built->forEachControlPoint([&](const glm::dvec3& p) {
        largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
      });
      EXPECT_EQ(net.largestCoordinate, largest);
      EXPECT_TRUE(net.verticesShown);
    }
  }
}

// Broken nets: the stream stops at the error the full parse reports, whatever the window: every
// file's non-finite values before α's range, the first bad value in each.
TEST_F(StreamedNet, StopsAtTheErrorTheFullParseReports) {
  FamilySpec aeb;
  aeb.construction = Construction::AlphaEB;
  aeb.degree = 5;
  const SurfaceModel wavy = test::wavyNet(aeb, 8, true);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> points = flat(wavy.points);
  const std::string aebDoc = R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, )"
                             R"("alpha": {"npy": "a.npy"}, "points": {"npy": "p.npy"}})";
  struct Case {
    std::string what;
    std::vector<double> points, alpha;
  };
  std::vector<Case> cases;
  auto withValue = [](std::vector<double> v, size_t k, double x) {
    v[k] = x;
    return v;
  };
  cases.push_back({"the last coordinate NaN", withValue(points, points.size() - 1, nan), wavy.alpha});
  cases.push_back({"a coordinate infinite in row 3", withValue(points, 3 * 8 * 3 + 4, -INFINITY), wavy.alpha});
  cases.push_back({"alpha NaN", points, withValue(wavy.alpha, 40, nan)});
  cases.push_back({"alpha 0", points, withValue(wavy.alpha, 17, 0.0)});
  cases.push_back({"alpha above 1 early, NaN late", points, withValue(withValue(wavy.alpha, 2, 1.5), 60, nan)});
  cases.push_back({"points NaN late, alpha 0 early", withValue(points, 150, nan), withValue(wavy.alpha, 0, 0.0)});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    write("p.npy", npyBytes("(8, 8, 3)", c.points));
    write("a.npy", npyBytes("(8, 8)", c.alpha));
    std::optional<Surface> built;
    const std::string expected = fullParse(aebDoc, built);
    ASSERT_NE(expected, "") << "the full parse accepts the broken net";
    const SampleLayout layout;
    for (size_t window : {size_t{1}, size_t{5}, size_t{64}}) {
      io::StreamedNet net;
      std::string fingerprint;
      EXPECT_EQ(streamed(aebDoc, window, layout, net, fingerprint), expected) << window;
    }
  }

  // Weights: a zero, a NaN after a zero, and w P overflowing.
  const SurfaceModel torus = test::nurbsTorus(3.0, 1.0);
  const std::string nurbsDoc = torusDoc(torus, "p.npy", "w.npy");
  std::vector<double> huge = flat(torus.points);
  huge[30] = 1e308;
  for (const auto& [what, pts, weights] :
       {std::tuple{"a weight 0", flat(torus.points), withValue(torus.weights, 20, 0.0)},
        std::tuple{"a weight NaN after a weight 0", flat(torus.points),
                   withValue(withValue(torus.weights, 5, 0.0), 70, nan)},
        std::tuple{"w P overflows", huge, withValue(torus.weights, 10, 4.0)}}) {
    SCOPED_TRACE(what);
    write("p.npy", npyBytes("(9, 9, 3)", pts));
    write("w.npy", npyBytes("(9, 9)", weights));
    std::optional<Surface> built;
    const std::string expected = fullParse(nurbsDoc, built);
    ASSERT_NE(expected, "");
    for (size_t window : {size_t{1}, size_t{4}, size_t{100}}) {
      io::StreamedNet net;
      std::string fingerprint;
      EXPECT_EQ(streamed(nurbsDoc, window, SampleLayout{}, net, fingerprint), expected) << window;
    }
  }
  // The same overflow with the weights written out in the model (the points still a file).
  SurfaceModel heavy = torus;
  heavy.weights[10] = 4.0;
  write("p.npy", npyBytes("(9, 9, 3)", huge));
  const std::string inlineDoc = torusDoc(heavy, "p.npy", "");
  std::optional<Surface> built;
  const std::string expected = fullParse(inlineDoc, built);
  ASSERT_NE(expected, "");
  for (size_t window : {size_t{1}, size_t{4}, size_t{100}}) {
    io::StreamedNet net;
    std::string fingerprint;
    EXPECT_EQ(streamed(inlineDoc, window, SampleLayout{}, net, fingerprint), expected) << window;
  }
}

// A net whose points or α make the vertex bound fail is not cleared by the stream: the caller then
// builds the surface, which checks every vertex (core/surface.h alphaEBVerticesSurelyFinite) and
// may find them all finite (α = 1e-306 on a net of size 1) or one that is not (α = 1e-308, size 100).
TEST_F(StreamedNet, LeavesTheVertexCheckToTheSurfaceWhenTheBoundFails) {
  FamilySpec aeb;
  aeb.construction = Construction::AlphaEB;
  aeb.degree = 5;
  struct Case {
    const char* alpha;
    double scale;
    bool shown, overflows;
  };
  for (const Case& c :
       {Case{"0.5", 1.0, true, false}, Case{"1e-306", 1.0, false, false}, Case{"1e-308", 100.0, false, true}}) {
    SCOPED_TRACE(c.alpha);
    write("p.npy", npyBytes("(6, 6, 3)", flat(test::wavyNet(aeb, 6, false, c.scale).points)));
    const std::string doc = std::string(R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": )") +
                            c.alpha + R"(, "points": {"npy": "p.npy"}})";
    io::StreamedNet net;
    std::string fingerprint;
    ASSERT_EQ(streamed(doc, 5, SampleLayout{}, net, fingerprint), "");
    EXPECT_EQ(net.verticesShown, c.shown);
    std::optional<Surface> built;
    const std::string error = fullParse(doc, built);
    EXPECT_EQ(error.empty(), !c.overflows) << error;
  }
}

// ---- Bands: io/streamed_bands.h --------------------------------------------------------------------

// Bands handed out while the net streams: contiguous over the rows asked for, each the whole
// surface's patchRows bit for bit; the fingerprint, α and magnitude are the built surface's, for
// windows that cut rows anywhere, bands of one row or of many, closed and open nets.
TEST_F(StreamedNet, BandsAreTheWholeSurfacesPatchRowsAndTheIdentityIsItsOwn) {
  FamilySpec aeb;
  aeb.construction = Construction::AlphaEB;
  aeb.degree = 5;
  SurfaceModel wavy = test::wavyNet(aeb, 9, true, 3.0);
  wavy.alpha[3] = wavy.alpha[40] = 1.0;
  write("net.npy", npyBytes("(9, 9, 3)", flat(wavy.points)));
  write("net32.npy", npyBytes("(9, 9, 3)", flat(wavy.points), false));
  write("alpha.npy", npyBytes("(9, 9)", wavy.alpha));
  nlohmann::json inlineAlpha = nlohmann::json::array();
  for (int i = 0; i < 9; ++i) inlineAlpha.push_back(std::vector<double>(wavy.alpha.begin() + 9 * i, wavy.alpha.begin() + 9 * i + 9));
  // A tall closed net: more rows than the ones kept apart at either end (kMaxBasisCount each), so
  // that bands read rows from the blocks between bands made of kept rows alone.
  SurfaceModel tall = test::wavyNet(aeb, 5, true, 2.0);
  tall.rows = 30;
  tall.points.clear();
  tall.alpha.clear();
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 5; ++j) {
      tall.points.push_back({std::cos(i * 0.2) + 0.1 * j, std::sin(i * 0.2), 0.3 * j + 0.01 * i * i});
      tall.alpha.push_back(0.3 + 0.02 * i + 0.01 * j);
    }
  write("tall.npy", npyBytes("(30, 5, 3)", flat(tall.points)));
  write("tall_alpha.npy", npyBytes("(30, 5)", tall.alpha));
  const std::string aebHead = R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, )";
  const std::vector<std::string> docs = {
      aebHead + R"("alpha": {"npy": "tall_alpha.npy"}, "closed": [true, false], "points": {"npy": "tall.npy"}})",
      aebHead + R"("alpha": {"npy": "tall_alpha.npy"}, "points": {"npy": "tall.npy"}})",
      R"({"kind": "surface", "construction": "ubp", "order": 6, "lambda": 0.5, "closed": [true, true], )"
      R"("points": {"npy": "tall.npy"}})",
      aebHead + R"("alpha": {"npy": "alpha.npy"}, "points": {"npy": "net.npy"}})",
      aebHead + R"("alpha": {"npy": "alpha.npy"}, "closed": [true, false], "points": {"npy": "net.npy"}})",
      aebHead + R"("alpha": {"npy": "alpha.npy"}, "closed": [true, true], "points": {"npy": "net32.npy"}})",
      aebHead + R"("alpha": 0.25, "closed": [true, false], "points": {"npy": "net.npy"}})",
      aebHead + R"("alpha": )" + inlineAlpha.dump() + R"(, "points": {"npy": "net.npy"}})",
      R"({"kind": "surface", "construction": "extended_bspline", "degree": 4, "closed": [true, false], )"
      R"("points": {"npy": "net.npy"}})",
      R"({"kind": "surface", "construction": "ubp", "order": 5, "lambda": 0.25, "points": {"npy": "net.npy"}})",
  };
  for (const std::string& doc : docs) {
    SCOPED_TRACE(doc);
    std::optional<Surface> built;
    ASSERT_EQ(fullParse(doc, built), "");
    const SampleLayout layout = gridLayout(*built);
    const std::string builtFingerprint = jobFingerprint(*built, layout, OutputFormat::RawF32);
    const JobMetadata full = jobMetadataOf(*built, "m.json", "", "cpu", Precision::Double, Precision::Double, 4, 4);
    const SpanRange all = built->patches().u;
    for (const SpanRange rows : {all, SpanRange{all.first + 1, all.last - 1}, SpanRange{all.last, all.last},
                                 SpanRange{0, -1}}) {
      for (const BandSizes sizes : {BandSizes{1, 1}, BandSizes{2, 1 << 20}, BandSizes{1, 300}}) {
        for (size_t window : {size_t{1}, size_t{7}, size_t{9}, size_t{kStreamWindowPoints}}) {
          const std::string what = "rows " + std::to_string(rows.first) + ".." + std::to_string(rows.last) +
                                   ", first band " + std::to_string(sizes.firstRows) + ", window " +
                                   std::to_string(window);
          ModelArrays arrays;
          const SurfaceModel outline = outlineOf(doc, arrays);
          ASSERT_TRUE(bandsCanStream(outline, arrays)) << what;
          SurfaceFingerprint f = fingerprintFor(outline, arrays, layout);
          int next = rows.first;
          const io::StreamedNet net = streamSurfaceBands(
              outline, arrays, f, rows,
              [&](const Surface& band, int first, int last) {
                EXPECT_EQ(first, next) << what;
                next = last + 1;
                const Surface expected = built->patchRows(first, last);
                ASSERT_EQ(band.patchNet().size(), expected.patchNet().size()) << what;
                EXPECT_EQ(std::memcmp(band.patchNet().data(), expected.patchNet().data(),
                                      band.patchNet().size() * sizeof(glm::dvec3)),
                          0)
                    << what << ": band " << first << ".." << last;
                EXPECT_EQ(band.alphas(), expected.alphas()) << what;
              },
              sizes, window);
          EXPECT_EQ(next, std::max(rows.first, rows.last + 1)) << what << ": the bands cover the rows";
          EXPECT_EQ(f.finish(), builtFingerprint) << what;
          const JobMetadata m = jobMetadataOf(built->model(), net.alpha, net.rational, "m.json", "", "cpu",
                                              Precision::Double, Precision::Double, 4, 4);
          EXPECT_EQ(metadataJson(m), metadataJson(full)) << what;
          EXPECT_TRUE(net.verticesShown) << what;
        }
      }
    }
  }
}

// A broken net stops the bands: every bad value the full parse refuses is refused (ModelError)
// before the bands after it, whatever the window; a V beyond fp64 is named by the band that holds
// it as the full parse names it. Which error comes first may differ from the full parse's (the
// caller runs that parse to name it).
TEST_F(StreamedNet, BandsStopAtABrokenNet) {
  FamilySpec aeb;
  aeb.construction = Construction::AlphaEB;
  aeb.degree = 5;
  const SurfaceModel wavy = test::wavyNet(aeb, 8, true);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> points = flat(wavy.points);
  const std::string doc = R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, )"
                          R"("alpha": {"npy": "a.npy"}, "points": {"npy": "p.npy"}})";
  auto withValue = [](std::vector<double> v, size_t k, double x) {
    v[k] = x;
    return v;
  };
  struct Case {
    std::string what;
    std::vector<double> points, alpha;
    int badRow;  // the first point row that holds a bad value
    int reach = 2;  // a band of patch rows ..last that sees it: its reads (last + 2), its vertices (last + 1)
  };
  const std::vector<Case> cases = {
      {"the last coordinate NaN", withValue(points, points.size() - 1, nan), wavy.alpha, 7},
      {"a coordinate infinite in row 3", withValue(points, 3 * 8 * 3 + 4, -INFINITY), wavy.alpha, 3},
      {"alpha NaN in row 5", points, withValue(wavy.alpha, 40, nan), 5},
      {"alpha 0 in row 2", points, withValue(wavy.alpha, 17, 0.0), 2},
      {"alpha 1e-310 in row 4 (V overflows)", points, withValue(wavy.alpha, 4 * 8 + 3, 1e-310), 4, 1},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    write("p.npy", npyBytes("(8, 8, 3)", c.points));
    write("a.npy", npyBytes("(8, 8)", c.alpha));
    std::optional<Surface> built;
    const std::string expected = fullParse(doc, built);
    ASSERT_NE(expected, "") << "the full parse accepts the broken net";
    for (size_t window : {size_t{1}, size_t{5}, size_t{64}}) {
      ModelArrays arrays;
      const SurfaceModel outline = outlineOf(doc, arrays);
      SurfaceFingerprint f = fingerprintFor(outline, arrays, SampleLayout{});
      int lastSampled = -1;
      try {
        (void)streamSurfaceBands(
            outline, arrays, f, patchRangeOf(outline).u, [&](const Surface&, int, int last) { lastSampled = last; },
            BandSizes{1, 1}, window);
        ADD_FAILURE() << "the bands accepted a broken net (window " << window << ")";
      } catch (const ModelError& e) {
        if (c.what.find("V overflows") != std::string::npos) {
          EXPECT_EQ(e.what(), expected) << window;
        }
      }
      // No band that sees the bad value was handed out.
      EXPECT_LT(lastSampled + c.reach, c.badRow) << window;
    }
  }
}

// ---- Curves: the same machinery, a curve's points for rows ------------------------------------------

// A curve streamed from its files hands out bands of spans that evaluate to the whole curve's bits
// (open and closed α-EB curves, whose wrapped spans read the first points at the end and the last
// at the start; α from a file or one number; a closed UBP curve; span knots), and its stream gives
// the built curve's fingerprint and metadata, for any band size, window and range of spans.
TEST_F(StreamedNet, CurveBandsAreTheWholeCurvesSpans) {
  constexpr int kN = 23;
  std::vector<double> xy, xyz, alpha;
  for (int i = 0; i < kN; ++i) {
    const double t = 0.27 * i;
    xy.insert(xy.end(), {std::cos(t) * (1.0 + 0.1 * i), std::sin(1.3 * t)});
    xyz.insert(xyz.end(), {std::cos(t), std::sin(t), 0.05 * i * i});
    alpha.push_back(0.2 + 0.7 * std::abs(std::sin(0.9 * i)));
  }
  write("c2.npy", npyBytes("(23, 2)", xy));
  write("c3.npy", npyBytes("(23, 3)", xyz));
  write("ca.npy", npyBytes("(23,)", alpha));
  nlohmann::json knots = nlohmann::json::array();
  for (int s = 0; s <= kN - 3; ++s) knots.push_back(0.5 * s + 0.01 * s * s);
  const std::string aeb = R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": 0.25, )";
  const std::vector<std::string> docs = {
      aeb + R"("alpha": {"npy": "ca.npy"}, "points": {"npy": "c2.npy"}})",
      aeb + R"("alpha": {"npy": "ca.npy"}, "closed": true, "points": {"npy": "c3.npy"}})",
      aeb + R"("alpha": 0.3, "closed": true, "points": {"npy": "c2.npy"}})",
      R"({"kind": "curve", "construction": "ubp", "order": 5, "lambda": 0.5, "closed": true, "points": {"npy": "c3.npy"}})",
      R"({"kind": "curve", "construction": "extended_bspline", "degree": 4, "knots": )" + knots.dump() +
          R"(, "points": {"npy": "c2.npy"}})",
  };
  for (const std::string& doc : docs) {
    SCOPED_TRACE(doc);
    write("m.json", doc);
    const Curve whole = Curve::create(std::get<CurveModel>(loadModelFile(dir_ / "m.json")));
    SampleLayout layout;
    layout.samplesU = 4;
    layout.fields = fieldBit(Field::Point);
    layout.totalItems = static_cast<size_t>(whole.spans().last - whole.spans().first + 1);
    const std::string builtFingerprint = jobFingerprint(whole.model(), layout, OutputFormat::RawF32);
    const JobMetadata full = jobMetadataOf(whole.model(), "m.json", "", "cpu", Precision::Double, Precision::Double, 4);
    const SpanRange all = whole.spans();
    for (const SpanRange spans : {all, SpanRange{all.first + 2, all.last - 3}, SpanRange{all.last, all.last},
                                  SpanRange{0, -1}}) {
      for (const BandSizes sizes : {BandSizes{1, 1}, BandSizes{2, 1 << 20}, BandSizes{1, 2000}}) {
        for (size_t window : {size_t{1}, size_t{7}, size_t{kStreamWindowPoints}}) {
          const std::string what = "spans " + std::to_string(spans.first) + ".." + std::to_string(spans.last) +
                                   ", first band " + std::to_string(sizes.firstRows) + ", window " +
                                   std::to_string(window);
          ModelArrays arrays;
          arrays.folder = dir_;
          arrays.outline = true;
          const CurveModel outline = std::get<CurveModel>(parseModelText(doc, &arrays));
          ASSERT_TRUE(outline.points.empty()) << "an outline read its points";
          ASSERT_TRUE(curveSpansCanStream(outline, arrays)) << what;
          const SurfaceCounts counts = outlineCounts(outline, arrays);
          CurveFingerprint f(outline, counts.points, counts.alpha, counts.weights, layout, OutputFormat::RawF32);
          int covered = spans.first;  // the bands handed out cover spans.first..covered - 1
          const io::StreamedNet net = streamCurveSpans(
              outline, arrays, f, spans,
              [&](const Curve& band, int first, int last) {
                EXPECT_LE(first, covered) << what;
                EXPECT_TRUE(last >= spans.first && first <= spans.last) << what << ": a band outside the spans";
                covered = std::max(covered, last + 1);
                ASSERT_EQ(band.spans().last, last - first) << what;
                for (int s = first; s <= last; ++s)
                  for (double t : {0.0, 0.3, 1.0}) {
                    const CurvePoint a = band.evaluate(s - first, t), b = whole.evaluate(s, t);
                    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << what << ": span " << s << " at " << t;
                  }
              },
              sizes, window);
          if (spans.first > spans.last) {
            EXPECT_EQ(covered, spans.first) << what << ": a band for no spans";
          } else {
            EXPECT_GE(covered, spans.last + 1) << what << ": the bands cover the spans";
          }
          EXPECT_EQ(f.finish(), builtFingerprint) << what;
          const JobMetadata m = jobMetadataOf(outline, net.alpha, net.rational, "m.json", "", "cpu", Precision::Double,
                                              Precision::Double, 4);
          EXPECT_EQ(metadataJson(m), metadataJson(full)) << what;
          EXPECT_TRUE(net.verticesShown) << what;
        }
      }
    }
  }
}

// A broken curve stops its stream with a ModelError, whatever the window and the spans asked for
// (an empty shard asks for none): a coordinate or α not finite, α out of (0,1], a V beyond fp64
// (named as the full parse names it).
TEST_F(StreamedNet, CurveStreamsStopAtABrokenCurve) {
  constexpr int kN = 12;
  std::vector<double> xy, alpha;
  for (int i = 0; i < kN; ++i) {
    xy.insert(xy.end(), {1e300 * std::cos(0.5 * i), 1e300 * std::sin(0.5 * i)});
    alpha.push_back(0.5);
  }
  auto withValue = [](std::vector<double> v, size_t k, double x) {
    v[k] = x;
    return v;
  };
  const std::string doc = R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, )"
                          R"("alpha": {"npy": "a.npy"}, "closed": true, "points": {"npy": "p.npy"}})";
  struct Case {
    std::string what;
    std::vector<double> points, alpha;
  };
  const std::vector<Case> cases = {
      {"the last coordinate NaN", withValue(xy, xy.size() - 1, std::numeric_limits<double>::quiet_NaN()), alpha},
      {"alpha 0 at 5", xy, withValue(alpha, 5, 0.0)},
      {"alpha 1.5 at 0", xy, withValue(alpha, 0, 1.5)},
      {"alpha 1e-300 at 11 (V overflows)", xy, withValue(alpha, 11, 1e-300)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    write("p.npy", npyBytes("(12, 2)", c.points));
    write("a.npy", npyBytes("(12,)", c.alpha));
    write("m.json", doc);
    std::string expected;
    try {
      (void)Curve::create(std::get<CurveModel>(loadModelFile(dir_ / "m.json")));
    } catch (const ModelError& e) {
      expected = e.what();
    }
    ASSERT_NE(expected, "") << "the full parse accepts the broken curve";
    for (size_t window : {size_t{1}, size_t{5}, size_t{64}}) {
      ModelArrays arrays;
      arrays.folder = dir_;
      arrays.outline = true;
      const CurveModel outline = std::get<CurveModel>(parseModelText(doc, &arrays));
      CurveFingerprint f(outline, kN, kN, 0, SampleLayout{}, OutputFormat::RawF32);
      try {
        (void)streamCurveSpans(outline, arrays, f, {0, -1}, {}, BandSizes{1, 1}, window);
        ADD_FAILURE() << "the stream accepted a broken curve (window " << window << ")";
      } catch (const ModelError& e) {
        if (c.what.find("V overflows") != std::string::npos) {
          EXPECT_EQ(e.what(), expected) << window;
        }
      }
    }
  }
}

}  // namespace
}  // namespace shapespline::io
