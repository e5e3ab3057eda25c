// `sample --trim` on imported faces (issue 32): the drilled plate's drilled faces sampled on a
// 256 x 256 grid keep no sample inside a hole, keep the face's area fraction of the samples, and
// keep the same samples on the CPU and on Vulkan; OCCT's own face classifier agrees with the trim
// loops on 10^5 random parameters; and the command refuses what --trim does not write.
#include "test_parts.h"

#include <shapespline/cad/part_import.h>
#include <shapespline/core/trim_classifier.h>
#include <shapespline/io/model_json.h>

#include <BRepClass_FaceClassifier.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <gp_Pnt2d.hxx>

#include <cli/cli_runner.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

struct TrimmedRecord {
  double u, v, x, y, z;
};

std::vector<TrimmedRecord> readRecords(const fs::path& f64) {
  const std::string bytes = readText(f64);
  std::vector<TrimmedRecord> out(bytes.size() / sizeof(TrimmedRecord));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(TrimmedRecord));
  EXPECT_EQ(bytes.size() % sizeof(TrimmedRecord), 0u);
  return out;
}

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

double distanceToLoops(const TrimLoops& trim, glm::dvec2 p) {
  double best = 1e300;
  for (const auto& loop : trim.loops)
    for (size_t i = 0; i < loop.size(); ++i) best = std::min(best, distanceToSegment(p, loop[i], loop[(i + 1) % loop.size()]));
  return best;
}

class TrimmedSampling : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new ScratchDir("trimmed_sampling");
    writeStep(drilledPlate(), *dir_ / "plate.step");
    cad::importPart(*dir_ / "plate.step", *dir_ / "plate");
    std::ifstream in(*dir_ / "plate" / "part.json");
    const nlohmann::json manifest = nlohmann::json::parse(in);
    for (const auto& face : manifest.at("faces"))
      if (face.at("loops").get<int>() == 3) drilled_.push_back(face.at("id").get<int>());
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path face(int id) {
    char name[32];
    std::snprintf(name, sizeof name, "face_%04d.json", id);
    return *dir_ / "plate" / name;
  }
  static ScratchDir* dir_;
  static std::vector<int> drilled_;
};
ScratchDir* TrimmedSampling::dir_ = nullptr;
std::vector<int> TrimmedSampling::drilled_;

TEST_F(TrimmedSampling, NoSampleInAHoleAndTheAreaFractionKept) {
  ASSERT_EQ(drilled_.size(), 2u);
  const double area = 100.0 * 60.0, holes = 2.0 * M_PI * 8.0 * 8.0;
  for (int id : drilled_) {
    SCOPED_TRACE(id);
    const fs::path out = *dir_ / ("cpu_" + std::to_string(id) + ".f64");
    const CliResult r = runCli("sample " + quote(face(id).string()) + " --grid 256 --trim --device cpu -o " + quote(out.string()), dir_->path());
    ASSERT_EQ(r.rc, 0) << r.err;
    const SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(face(id)));
    const double tolerance3d = model.trim.tolerance;  // a plane's parameters are its lengths here
    const std::vector<TrimmedRecord> kept = readRecords(out);
    for (const TrimmedRecord& k : kept)
      for (const Hole& h : drilledPlateHoles())
        ASSERT_GE(std::hypot(k.x - h.x, k.y - h.y), h.radius - 2.0 * tolerance3d) << k.x << ", " << k.y;
    const double fraction = double(kept.size()) / (256.0 * 256.0), expected = (area - holes) / area;
    EXPECT_NEAR(fraction / expected, 1.0, 0.01) << kept.size();

    // The same samples on Vulkan: the choice is made on the parameters, so the (U, V) are the same
    // bits and the points agree to fp64.
    const fs::path gpu = *dir_ / ("gpu_" + std::to_string(id) + ".f64");
    const CliResult g = runCli("sample " + quote(face(id).string()) + " --grid 256 --trim --device vulkan --require-device "
                               "--precision double -o " + quote(gpu.string()), dir_->path());
    if (g.rc == 3 && g.err.find("vulkan") != std::string::npos) continue;  // no device on this machine
    ASSERT_EQ(g.rc, 0) << g.err;
    const std::vector<TrimmedRecord> onGpu = readRecords(gpu);
    ASSERT_EQ(onGpu.size(), kept.size());
    for (size_t k = 0; k < kept.size(); ++k) {
      ASSERT_EQ(onGpu[k].u, kept[k].u);
      ASSERT_EQ(onGpu[k].v, kept[k].v);
      ASSERT_NEAR(onGpu[k].x, kept[k].x, 1e-12 * 120.0);
      ASSERT_NEAR(onGpu[k].y, kept[k].y, 1e-12 * 120.0);
    }
  }
}

// OCCT's BRepClass_FaceClassifier on the face itself against the trim loops of its model: the
// drilled faces are planes, whose B-spline keeps the face's parameters.
TEST_F(TrimmedSampling, OcctsFaceClassifierAgrees) {
  ASSERT_EQ(drilled_.size(), 2u);
  STEPControl_Reader reader;
  ASSERT_EQ(reader.ReadFile((*dir_ / "plate.step").c_str()), IFSelect_RetDone);
  reader.TransferRoots();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(reader.OneShape(), TopAbs_FACE, faces);
  std::mt19937_64 random(5);
  for (int id : drilled_) {
    SCOPED_TRACE(id);
    const SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(face(id)));
    const TrimClassifier ours(model.trim);
    const TopoDS_Face occtFace = TopoDS::Face(faces(id));
    std::uniform_real_distribution<double> U(model.knotsU[1], model.knotsU[2]), V(model.knotsV[1], model.knotsV[2]);
    int disagree = 0;
    const int samples = 100000;
    for (int k = 0; k < samples; ++k) {
      const glm::dvec2 p(U(random), V(random));
      BRepClass_FaceClassifier occt(occtFace, gp_Pnt2d(p.x, p.y), 1e-7);
      const bool occtInside = occt.State() != TopAbs_OUT;
      if (occtInside == ours.inside(p)) continue;
      ++disagree;
      // Between the edge and its polyline: within the polyline's tolerance of it.
      ASSERT_LE(distanceToLoops(model.trim, p), model.trim.tolerance) << p.x << ", " << p.y;
    }
    EXPECT_LE(disagree, samples / 1000);
  }
}

TEST_F(TrimmedSampling, RefusesPicturesShardsAndModelsWithoutLoops) {
  ASSERT_EQ(drilled_.size(), 2u);
  const std::string model = quote(face(drilled_.at(0)).string());
  // An SVG of a trimmed face is not made (a mesh or a point cloud is).
  CliResult r = runCli("sample " + model + " --trim -o " + quote((*dir_ / "x.svg").string()), dir_->path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("point cloud"), std::string::npos) << r.err;
  // Trimmed shards go to formats that carry their identity (tests/cli/part_shards_test.cpp).
  r = runCli("sample " + model + " --trim --shard 1/2 -o " + quote((*dir_ / "x.csv").string()), dir_->path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("--shard"), std::string::npos) << r.err;
  r = runCli("sample " + quote(examplesDir() + "/surface_aeb.json") + " --trim -o " + quote((*dir_ / "y.npy").string()),
             dir_->path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("no trim loops"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(*dir_ / "x.svg"));
  EXPECT_FALSE(fs::exists(*dir_ / "x.csv"));
  EXPECT_FALSE(fs::exists(*dir_ / "y.npy"));
}

// `sample part.json`: every face of the filleted box, trimmed, in one cloud whose records carry the
// face id; each face's records are exactly those of `sample FACE --trim` for that face, and every
// point lies on the box.
TEST(PartSampling, OneCloudWithAFaceColumnEqualToTheFacesSampledAlone) {
  ScratchDir dir("part_sampling");
  writeStep(filletedBox(), dir / "box.step");
  cad::importPart(dir / "box.step", dir / "box");
  const CliResult r = runCli("sample " + quote((dir / "box" / "part.json").string()) + " --grid 12 --device cpu -o " +
                                 quote((dir / "cloud.f64").string()),
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  struct Record {
    double face, u, v, x, y, z;
  };
  const std::string bytes = readText(dir / "cloud.f64");
  ASSERT_EQ(bytes.size() % sizeof(Record), 0u);
  std::vector<Record> cloud(bytes.size() / sizeof(Record));
  std::memcpy(cloud.data(), bytes.data(), bytes.size());
  std::ifstream in(dir / "box" / "part.json");
  const nlohmann::json manifest = nlohmann::json::parse(in);
  size_t next = 0;
  for (const auto& face : manifest.at("faces")) {
    const int id = face.at("id").get<int>();
    SCOPED_TRACE(id);
    const fs::path alone = dir / ("face" + std::to_string(id) + ".f64");
    const CliResult f = runCli("sample " + quote((dir / "box" / face.at("model").get<std::string>()).string()) +
                                   " --grid 12 --trim --device cpu -o " + quote(alone.string()),
                               dir.path());
    ASSERT_EQ(f.rc, 0) << f.err;
    const std::vector<TrimmedRecord> records = readRecords(alone);
    ASSERT_GT(records.size(), 0u);
    ASSERT_LE(next + records.size(), cloud.size());
    for (const TrimmedRecord& t : records) {
      const Record& c = cloud[next++];
      ASSERT_EQ(c.face, id);
      ASSERT_EQ(std::memcmp(&c.u, &t, sizeof t), 0);
      EXPECT_GE(c.x, -1e-9);
      EXPECT_LE(c.x, 40.0 + 1e-9);
      EXPECT_GE(c.y, -1e-9);
      EXPECT_LE(c.y, 30.0 + 1e-9);
      EXPECT_GE(c.z, -1e-9);
      EXPECT_LE(c.z, 20.0 + 1e-9);
    }
  }
  EXPECT_EQ(next, cloud.size());

}

}  // namespace
}  // namespace shapespline::test
