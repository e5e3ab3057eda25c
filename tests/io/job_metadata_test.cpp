// io/job_metadata.h: the SHA-256 of a file equals coreutils' sha256sum (a hasher we did not write)
// and the FIPS 180-2 vectors; comment lines stay one line each whatever the text; the α list is in
// full up to kMetadataCommentListMax values, else count/min/max; the singular (α = 1) vertices;
// the JSON round-trips through metadataFromJson, which names the key it refuses.
#include <shapespline/io/job_metadata.h>

#include <shapespline/version.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <unistd.h>

namespace shapespline::io {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

JobMetadata curveMetadata() {
  JobMetadata m;
  m.toolVersion = "0.1.0";
  m.toolCommit = "abc1234";
  m.modelFile = "models/open.json";
  m.modelSha256 = std::string(64, 'a');
  m.construction = Construction::AlphaEB;
  m.degree = 5;
  m.lambda = -2.5;
  m.setAlpha({0.5, 1.0, 0.25, 1.0}, 0, 0);
  m.device = "cpu";
  m.computedPrecision = Precision::Double;
  m.outputPrecision = Precision::Float;
  m.samplesU = 7;
  return m;
}

JobMetadata surfaceMetadata(int rows, int cols) {
  JobMetadata m = curveMetadata();
  m.surface = true;
  m.setAlpha(std::vector<double>(static_cast<size_t>(rows) * static_cast<size_t>(cols), 0.5), rows, cols);
  m.samplesU = 3;
  m.samplesV = 4;
  return m;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> v;
  size_t pos = 0;
  while (pos < text.size()) {
    const size_t nl = text.find('\n', pos);
    EXPECT_NE(nl, std::string::npos) << "the text ends without a newline";
    if (nl == std::string::npos) break;
    v.push_back(text.substr(pos, nl - pos));
    pos = nl + 1;
  }
  return v;
}

// The value of "PREFIX key: value" in the comment lines, or "(missing)".
std::string commentValue(const std::string& text, const std::string& prefix, const std::string& key) {
  for (const std::string& l : lines(text)) {
    if (l.rfind(prefix + key + ": ", 0) == 0) return l.substr(prefix.size() + key.size() + 2);
  }
  return "(missing)";
}

class TempFile {
 public:
  explicit TempFile(const std::string& bytes) {
    static int count = 0;
    path_ = fs::temp_directory_path() /
            ("shapespline_sha_" + std::to_string(::getpid()) + "_" + std::to_string(count++) + ".bin");
    std::ofstream(path_, std::ios::binary) << bytes;
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string sha256sum(const fs::path& p) {
  FILE* f = ::popen(("sha256sum '" + p.string() + "'").c_str(), "r");
  if (!f) return "(no sha256sum)";
  char buf[256] = {};
  const size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  ::pclose(f);
  return std::string(buf, n).substr(0, 64);
}

TEST(JobMetadata, Sha256MatchesKnownVectorsAndSha256sum) {
  // FIPS 180-2, appendix B.1 and the empty message.
  EXPECT_EQ(sha256Of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256Of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // Several read pieces (64 KiB each) and a ragged end.
  std::mt19937 rng(7);
  std::string bytes(300'001, '\0');
  for (char& c : bytes) c = static_cast<char>(rng());
  const TempFile file(bytes);
  const std::string digest = sha256OfFile(file.path());
  EXPECT_EQ(digest, sha256Of(bytes));
  if (std::system("command -v sha256sum >/dev/null 2>&1") != 0) GTEST_SKIP() << "no sha256sum";
  EXPECT_EQ(digest, sha256sum(file.path()));
  const std::string model = std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/models/surface_aeb.json";
  EXPECT_EQ(sha256OfFile(model), sha256sum(model));
}

TEST(JobMetadata, Sha256OfFileRefusesWhatItCannotRead) {
  EXPECT_THROW(sha256OfFile("/nonexistent/shapespline/model.json"), std::runtime_error);
  EXPECT_THROW(sha256OfFile(fs::temp_directory_path()), std::runtime_error);  // a folder
}

// The model's digest is that of the model file's bytes followed by each array's, whichever order
// the files arrive in relative to the hashing thread; it fails on a file it cannot read, and a
// digest dropped unread (the job failed before its metadata) stops without waiting for the rest.
// Files of 256 KiB or less in all are hashed by get() (the model alone here, the model and `alpha`
// below); `points` takes them over that, so that a thread hashes from then on.
TEST(JobMetadata, ModelDigestHashesTheModelThenItsArrays) {
  std::mt19937 rng(11);
  auto randomBytes = [&](size_t n) {
    std::string b(n, '\0');
    for (char& c : b) c = static_cast<char>(rng());
    return b;
  };
  const std::string model = randomBytes(1'000), points = randomBytes(200'003), alpha = randomBytes(70'000);
  const TempFile m(model), p(points), a(alpha);
  EXPECT_EQ(modelSha256(m.path(), {}), sha256Of(model));
  EXPECT_EQ(modelSha256(m.path(), {p.path(), a.path()}), sha256Of(model + points + alpha));
  EXPECT_NE(modelSha256(m.path(), {a.path(), p.path()}), sha256Of(model + points + alpha));  // the order counts
  {
    ModelDigest late(m.path());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the model file is likely hashed by now
    late.add(p.path());
    late.add(a.path());
    EXPECT_EQ(late.get(), sha256Of(model + points + alpha));
  }
  EXPECT_EQ(modelSha256(m.path(), {a.path()}), sha256Of(model + alpha));
  ModelDigest missing(m.path());
  missing.add("/nonexistent/shapespline/net.npy");
  EXPECT_THROW(missing.get(), std::runtime_error);
  {
    const TempFile gone("small");
    ModelDigest small(m.path());
    small.add(gone.path());  // small: hashed by get(), which no longer finds it
    fs::remove(gone.path());
    EXPECT_THROW(small.get(), std::runtime_error);
  }
  EXPECT_THROW(modelSha256("/nonexistent/shapespline/model.json", {p.path()}), std::runtime_error);
  const TempFile b(randomBytes(size_t{32} << 20));
  const auto start = std::chrono::steady_clock::now();
  {
    ModelDigest dropped(m.path());
    for (int k = 0; k < 100; ++k) dropped.add(b.path());
  }
  // Hashing the 3.2 GB added would take two seconds or more (OpenSSL: 1.7 GB/s with SHA
  // instructions); a dropped digest stops after the 64 KiB piece it is at.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(500));
}

TEST(JobMetadata, BuilderTakesTheModelAndThisBuild) {
  CurveModel c;
  c.family.construction = Construction::AlphaEB;
  c.family.degree = 5;
  c.family.lambda = 0.25;
  c.family.order = 9;  // not used by alpha_eb: not recorded
  c.points.resize(3);
  c.alpha = {1.0, 0.5, 1.0};
  const std::string model = std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/models/open_aeb.json";
  const JobMetadata m = jobMetadataOf(c, model, modelSha256(model, {}), "llvmpipe", Precision::Float, Precision::Float, 9);
  EXPECT_EQ(m.toolVersion, SHAPESPLINE_VERSION_STRING);
  EXPECT_EQ(m.toolCommit, SHAPESPLINE_GIT_COMMIT);
  EXPECT_EQ(m.modelFile, model);
  EXPECT_EQ(m.modelSha256, sha256OfFile(model));
  EXPECT_EQ(m.order, 0);
  EXPECT_EQ(m.grid(), "9");
  EXPECT_EQ(m.singularVertices(), (std::vector<std::pair<int, int>>{{0, 0}, {2, 0}}));
  EXPECT_EQ(metadataFromJson(metadataJson(m)), m);

  SurfaceModel s;
  s.family.construction = Construction::BSpline;
  s.family.order = 3;
  s.orderV = 4;
  s.rows = s.cols = 4;
  s.knotsU = {0, 0, 0, 0.5, 1, 1, 1};  // order 3: 4 + 3 knots
  s.knotsV = {0, 0, 0, 0, 1, 1, 1, 1};
  s.points.assign(16, glm::dvec3(0.0));
  const JobMetadata b = jobMetadataOf(Surface::create(s), model, modelSha256(model, {}), "cpu", Precision::Double, Precision::Double, 5, 6);
  EXPECT_EQ(b.grid(), "5x6");
  const json j = metadataJson(b);
  EXPECT_EQ(j["order"], json::array({3, 4}));
  EXPECT_FALSE(j.contains("lambda"));
  EXPECT_FALSE(j.contains("alpha"));
  EXPECT_FALSE(j.contains("singular_vertices"));
  EXPECT_FALSE(j.contains("rational"));
  EXPECT_EQ(metadataFromJson(j), b);

  // A rational B-spline says so ("rational": true, and a comment line); it is another job than the
  // same net without weights.
  s.weights.assign(16, 0.5);
  const JobMetadata r = jobMetadataOf(Surface::create(s), model, modelSha256(model, {}), "cpu", Precision::Double, Precision::Double, 5, 6);
  EXPECT_TRUE(r.rational);
  EXPECT_EQ(metadataJson(r)["rational"], true);
  EXPECT_NE(metadataComments(r, "# ").find("# rational: true\n"), std::string::npos);
  EXPECT_EQ(metadataFromJson(metadataJson(r)), r);
  EXPECT_EQ(metadataDifference(b, r), "rational");
  json notBSpline = metadataJson(curveMetadata());
  notBSpline["rational"] = true;
  EXPECT_THROW((void)metadataFromJson(notBSpline), MetadataError);
  json falseFlag = metadataJson(r);
  falseFlag["rational"] = false;  // absent, not false, is what a non-rational job writes
  EXPECT_THROW((void)metadataFromJson(falseFlag), MetadataError);
}

TEST(JobMetadata, SingularVerticesAreTheAlphaOneVertices) {
  JobMetadata c = curveMetadata();
  EXPECT_EQ(c.singularVertices(), (std::vector<std::pair<int, int>>{{1, 0}, {3, 0}}));
  EXPECT_EQ(metadataJson(c)["singular_vertices"], json::array({1, 3}));
  c.setAlpha({0.999999999, 1.0000000001}, 0, 0);  // only exactly 1
  EXPECT_TRUE(c.singularVertices().empty());

  JobMetadata s = surfaceMetadata(3, 4);
  std::vector<double> a = s.alpha;
  a[1 * 4 + 2] = 1.0;
  a[2 * 4 + 0] = 1.0;
  s.setAlpha(a, 3, 4);
  const json j = metadataJson(s);
  EXPECT_EQ(j["singular_vertices"], json::parse("[[1, 2], [2, 0]]"));
  ASSERT_EQ(j["alpha"].size(), 3u);  // rows of the net, as in model files
  EXPECT_EQ(j["alpha"][1].size(), 4u);
  EXPECT_EQ(j["alpha"][1][2], 1.0);
  EXPECT_EQ(commentValue(metadataComments(s, "# "), "# ", "singular_vertices"), "[[1, 2], [2, 0]]");

  // A family without α has neither key.
  JobMetadata g = curveMetadata();
  g.construction = Construction::GB;
  g.setAlpha({1.0}, 0, 0);
  EXPECT_FALSE(metadataJson(g).contains("singular_vertices"));
  EXPECT_EQ(commentValue(metadataComments(g, "# "), "# ", "alpha"), "(missing)");
}

TEST(JobMetadata, CommentLinesHoldEveryKeyOnePerLine) {
  JobMetadata m = curveMetadata();
  const std::string text = metadataComments(m, "comment ");
  for (const std::string& l : lines(text)) EXPECT_EQ(l.rfind("comment ", 0), 0u) << l;
  EXPECT_EQ(commentValue(text, "comment ", "tool_version"), "shapespline 0.1.0 (commit abc1234)");
  EXPECT_EQ(commentValue(text, "comment ", "model_file"), "models/open.json");
  EXPECT_EQ(commentValue(text, "comment ", "model_sha256"), std::string(64, 'a'));
  EXPECT_EQ(commentValue(text, "comment ", "kind"), "curve");
  EXPECT_EQ(commentValue(text, "comment ", "construction"), "alpha_eb");
  EXPECT_EQ(commentValue(text, "comment ", "degree"), "5");
  EXPECT_EQ(commentValue(text, "comment ", "lambda"), "-2.5");
  EXPECT_EQ(commentValue(text, "comment ", "alpha"), "[0.5, 1, 0.25, 1]");
  EXPECT_EQ(commentValue(text, "comment ", "singular_vertices"), "[1, 3]");
  EXPECT_EQ(commentValue(text, "comment ", "device"), "cpu");
  EXPECT_EQ(commentValue(text, "comment ", "computed_precision"), "double");
  EXPECT_EQ(commentValue(text, "comment ", "output_precision"), "float");
  EXPECT_EQ(commentValue(text, "comment ", "grid"), "7");
  EXPECT_EQ(commentValue(text, "comment ", "mu"), "(missing)");  // alpha_eb has no μ
  EXPECT_EQ(lines(text).size(), 13u);

  JobMetadata g = curveMetadata();
  g.construction = Construction::GUBP;
  g.order = 5;
  g.mu = {0.25, -1.0, 3.0};
  const std::string gt = metadataComments(g, "# ");
  EXPECT_EQ(commentValue(gt, "# ", "mu"), "[0.25, -1, 3]");
  EXPECT_EQ(commentValue(gt, "# ", "order"), "5");
  EXPECT_EQ(commentValue(gt, "# ", "lambda"), "(missing)");
  EXPECT_EQ(commentValue(gt, "# ", "degree"), "(missing)");
}

TEST(JobMetadata, TextValuesAreEscapedOntoOneLine) {
  JobMetadata m = curveMetadata();
  m.modelFile = "evil\nend_header\r\n# v 1 2 3\t\"q\"\\\x01.json";
  m.device = "GPU\nv 0 0 0";
  m.toolCommit = "abc\n";
  const std::string text = metadataComments(m, "# ");
  const auto all = lines(text);
  EXPECT_EQ(all.size(), 13u) << text;
  for (const std::string& l : all) EXPECT_EQ(l.rfind("# ", 0), 0u) << l;
  EXPECT_EQ(commentValue(text, "# ", "model_file"), "evil\\nend_header\\r\\n# v 1 2 3\\t\\\"q\\\"\\\\\\u0001.json");
  EXPECT_EQ(commentValue(text, "# ", "device"), "GPU\\nv 0 0 0");
  EXPECT_EQ(commentValue(text, "# ", "tool_version"), "shapespline 0.1.0 (commit abc\\n)");
  // The JSON keeps the text (JSON escapes it itself); invalid UTF-8 becomes U+FFFD so it can be written.
  EXPECT_EQ(metadataJson(m)["model_file"], m.modelFile);
  m.modelFile = "bad\xff\xfe.json";
  EXPECT_EQ(metadataJson(m)["model_file"], "bad\xef\xbf\xbd\xef\xbf\xbd.json");
  EXPECT_NO_THROW((void)metadataJson(m).dump());
  EXPECT_EQ(commentValue(metadataComments(m, "# "), "# ", "model_file"), "bad\\ufffd\\ufffd.json");
}

TEST(JobMetadata, CommentAlphaListIsCappedTheJsonLater) {
  JobMetadata m = curveMetadata();
  std::vector<double> a(kMetadataCommentListMax, 0.5);
  a[3] = 1.0;
  m.setAlpha(a, 0, 0);
  std::string listed = commentValue(metadataComments(m, "# "), "# ", "alpha");
  EXPECT_EQ(std::count(listed.begin(), listed.end(), ','), static_cast<long>(kMetadataCommentListMax - 1)) << listed;

  a.assign(kMetadataCommentListMax + 1, 0.5);
  a[7] = 0.125;
  a[9] = 1.0;
  m.setAlpha(a, 0, 0);
  EXPECT_EQ(commentValue(metadataComments(m, "# "), "# ", "alpha"), "65 values, min 0.125, max 1");
  EXPECT_EQ(commentValue(metadataComments(m, "# "), "# ", "singular_vertices"), "[9]");
  EXPECT_EQ(metadataJson(m)["alpha"].size(), kMetadataCommentListMax + 1);

  // A surface: rows while they fit, then count (rows x cols), min, max; the singular list capped too.
  JobMetadata s = surfaceMetadata(2, 3);
  s.setAlpha({0.5, 1, 0.25, 1, 0.5, 0.75}, 2, 3);
  EXPECT_EQ(commentValue(metadataComments(s, "# "), "# ", "alpha"), "[[0.5, 1, 0.25], [1, 0.5, 0.75]]");
  JobMetadata big = surfaceMetadata(10, 10);
  a.assign(100, 1.0);
  a[0] = 0.5;
  big.setAlpha(a, 10, 10);
  const std::string bt = metadataComments(big, "# ");
  EXPECT_EQ(commentValue(bt, "# ", "alpha"), "100 values (10x10), min 0.5, max 1");
  EXPECT_EQ(commentValue(bt, "# ", "singular_vertices"), "99 vertices with alpha = 1");
  EXPECT_EQ(metadataJson(big)["singular_vertices"].size(), 99u);
  EXPECT_LT(bt.size(), 2000u);
}

TEST(JobMetadata, LargeAlphaIsSummarisedNotListed) {
  // A 4096 x 4096 net would list 16.8 million values in every sidecar; past kMetadataAlphaListMax
  // the JSON holds count, shape, range and the number of α = 1 vertices.
  JobMetadata s = surfaceMetadata(64, 64);  // exactly the limit: still listed
  EXPECT_TRUE(metadataJson(s)["alpha"].is_array());
  std::vector<double> a(65 * 64, 0.5);
  a[5] = 1.0;
  a[70] = 1.0;
  a[100] = 0.25;
  s.setAlpha(a, 65, 64);
  EXPECT_TRUE(s.alpha.empty());
  const json j = metadataJson(s);
  EXPECT_EQ(j["alpha"], json::parse(R"({"values": 4160, "shape": [65, 64], "min": 0.25, "max": 1.0})"));
  EXPECT_EQ(j["singular_vertices"], json::parse(R"({"count": 2})"));
  EXPECT_EQ(metadataFromJson(json::parse(j.dump())), s);
  EXPECT_EQ(commentValue(metadataComments(s, "# "), "# ", "alpha"), "4160 values (65x64), min 0.25, max 1");
  EXPECT_EQ(commentValue(metadataComments(s, "# "), "# ", "singular_vertices"), "2 vertices with alpha = 1");
  JobMetadata other = s;
  a[71] = 1.0;
  other.setAlpha(a, 65, 64);
  EXPECT_EQ(metadataDifference(s, other), "alpha");

  JobMetadata c = curveMetadata();
  c.setAlpha(std::vector<double>(5000, 1.0), 0, 0);
  EXPECT_EQ(metadataJson(c)["alpha"]["shape"], json::array({5000}));
  EXPECT_EQ(metadataFromJson(metadataJson(c)), c);

  auto refused = [&](const std::function<void(json&)>& change) {
    json bad = j;
    change(bad);
    try {
      (void)metadataFromJson(bad);
    } catch (const MetadataError& e) {
      return e.key();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(refused([](json&) {}), "(accepted)");
  EXPECT_EQ(refused([](json& b) { b["alpha"]["values"] = 4159; }), "metadata.alpha.values");
  EXPECT_EQ(refused([](json& b) { b["alpha"]["shape"] = json::array({4160}); }), "metadata.alpha.shape");
  EXPECT_EQ(refused([](json& b) { b["alpha"]["min"] = 2.0; }), "metadata.alpha");
  EXPECT_EQ(refused([](json& b) { b["alpha"]["max"] = 0.75; }), "metadata.singular_vertices.count");
  EXPECT_EQ(refused([](json& b) { b["singular_vertices"] = json::array(); }), "metadata.singular_vertices");
  EXPECT_EQ(refused([](json& b) { b["singular_vertices"]["count"] = 4161; }), "metadata.singular_vertices.count");
  EXPECT_EQ(refused([](json& b) { b["alpha"]["extra"] = 1; }), "metadata.alpha");
  // A short net summarised, or a long one listed, is not what this tool writes.
  json small = metadataJson(surfaceMetadata(2, 2));
  small["alpha"] = j["alpha"];
  small["alpha"]["values"] = 4;
  small["alpha"]["shape"] = json::array({2, 2});
  EXPECT_THROW((void)metadataFromJson(small), MetadataError);
}

TEST(JobMetadata, JsonRoundTripsAndRefusesOthers) {
  for (const JobMetadata& m : {curveMetadata(), surfaceMetadata(2, 5)}) {
    const json j = metadataJson(m);
    EXPECT_EQ(metadataFromJson(j), m);
    EXPECT_EQ(metadataJson(metadataFromJson(json::parse(j.dump()))).dump(), j.dump());
    EXPECT_EQ(j["tool"], "shapespline");
    EXPECT_EQ(j["grid"], m.surface ? "3x4" : "7");
  }
  // A layout's default metadata (a writer used without the command line) reads back too.
  EXPECT_EQ(metadataFromJson(metadataJson(JobMetadata{})), JobMetadata{});
  const json good = metadataJson(curveMetadata());
  auto refusedKey = [&](const std::function<void(json&)>& change) {
    json j = good;
    change(j);
    try {
      (void)metadataFromJson(j);
    } catch (const MetadataError& e) {
      return e.key();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(refusedKey([](json& j) { j.erase("lambda"); }), "metadata.lambda");
  EXPECT_EQ(refusedKey([](json& j) { j["lambda"] = "x"; }), "metadata.lambda");
  EXPECT_EQ(refusedKey([](json& j) { j["mu"] = json::array(); }), "metadata");  // a key alpha_eb does not use
  EXPECT_EQ(refusedKey([](json& j) { j["construction"] = "nurbs"; }), "metadata.construction");
  EXPECT_EQ(refusedKey([](json& j) { j["singular_vertices"] = json::array({0}); }), "metadata.singular_vertices");
  EXPECT_EQ(refusedKey([](json& j) { j["model_sha256"] = "ABC"; }), "metadata.model_sha256");
  EXPECT_EQ(refusedKey([](json& j) { j["grid"] = "3x4"; }), "metadata.grid");  // a curve has one count
  EXPECT_EQ(refusedKey([](json& j) { j["grid"] = "1"; }), "metadata.grid");
  EXPECT_EQ(refusedKey([](json& j) { j["computed_precision"] = "half"; }), "metadata.computed_precision");
  EXPECT_EQ(refusedKey([](json& j) { j["alpha"][0] = "1"; }), "metadata.alpha");
  EXPECT_EQ(refusedKey([](json& j) { j = json::array(); }), "metadata");
  EXPECT_EQ(refusedKey([](json&) {}), "(accepted)");
}

TEST(JobMetadata, DifferenceNamesTheFirstKey) {
  const JobMetadata a = curveMetadata();
  EXPECT_EQ(metadataDifference(a, a), "");
  JobMetadata b = a;
  b.setAlpha({0.5, 1.0, 0.75, 1.0}, 0, 0);
  EXPECT_EQ(metadataDifference(a, b), "alpha");
  b = a;
  b.modelSha256 = std::string(64, 'b');
  EXPECT_EQ(metadataDifference(a, b), "model_sha256");
  b = a;
  b.lambda = -b.lambda;
  EXPECT_EQ(metadataDifference(a, b), "lambda");
  b = a;
  b.device = "llvmpipe";
  EXPECT_EQ(metadataDifference(a, b), "device");
  b = a;
  b.samplesU = 8;
  EXPECT_EQ(metadataDifference(a, b), "grid");
}

}  // namespace
}  // namespace shapespline::io
