// Imported faces on Vulkan (issue 32): 10^4 random parameters a face, evaluated as a list by
// sampling::Session on the device in fp64 and fp32, against OCCT's own D1 of the B-spline it
// converted the face to. Validation layers on.
// The Vulkan headers first: OCCT defines a macro `Handle`, which vk::Handle's declaration must
// not meet.
#include <shapespline/sampling/session.h>
#include <support/vk_fixture.h>

#include "test_parts.h"

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>

#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <fstream>
#include <random>
#include <unistd.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using sampling::DeviceKind;

constexpr int kSamplesPerFace = 10000;

class ImportedFacesOnGpu : public VulkanTest {
 protected:
  void SetUp() override {
    VulkanTest::SetUp();
    if (IsSkipped()) return;
    dir_ = fs::temp_directory_path() / ("shapespline_cad_gpu_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    VulkanTest::TearDown();
  }
  fs::path dir_;
};

double derivativeScale(const std::vector<double>& knots, int order) {
  double shortest = 1e300;
  for (size_t i = static_cast<size_t>(order - 1); i + order < knots.size(); ++i)  // the domain's intervals
    if (knots[i + 1] > knots[i]) shortest = std::min(shortest, knots[i + 1] - knots[i]);
  return (order - 1) / shortest;
}

double boxDiagonal(const std::vector<glm::dvec3>& points) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

// fp64: 1e-12 of the face's size; fp32: 1e-6 of the part's (issue 32: fp32 rounds each coordinate
// to its ulp, so a small fillet far from the origin is held to the part's box, not its own).
// Derivatives: the same relative bound on their own scale, size x (order - 1) / the shortest knot
// interval (a B-spline's derivative is a B-spline of pole differences over knot intervals).
TEST_F(ImportedFacesOnGpu, EveryFaceMatchesOcctInFp64AndFp32) {
  sampling::Session session(ctx_);
  std::mt19937_64 random(42);
  int faces = 0;
  for (const TestPart& part : allTestParts()) {
    const fs::path file = dir_ / (part.name + ".step"), out = dir_ / part.name;
    writeStep(part.shape, file);
    cad::importPart(file, out);
    std::ifstream in(out / "part.json");
    const json manifest = json::parse(in);
    const cad::PartShape occtPart = cad::readPart(file, std::uint64_t{1} << 30);
    TopTools_IndexedMapOfShape occtFaces;
    TopExp::MapShapes(occtPart.shape, TopAbs_FACE, occtFaces);
    std::vector<SurfaceModel> models;
    std::vector<glm::dvec3> allPoles;
    for (const json& entry : manifest.at("faces")) {
      ASSERT_FALSE(entry.at("model").is_null());
      models.push_back(std::get<SurfaceModel>(io::loadModelFile(out / entry.at("model").get<std::string>())));
      allPoles.insert(allPoles.end(), models.back().points.begin(), models.back().points.end());
    }
    const double partSize = boxDiagonal(allPoles);
    size_t index = 0;
    for (const json& entry : manifest.at("faces")) {
      SCOPED_TRACE(part.name + " face " + std::to_string(entry.at("id").get<int>()));
      const SurfaceModel& model = models[index++];
      const Surface surface = Surface::create(model);
      const cad::ConvertedFace occt = cad::convertFace(TopoDS::Face(occtFaces(entry.at("id").get<int>())), 1e-5);
      const auto [a0, a1] = surface.parameterRangeU();
      const auto [b0, b1] = surface.parameterRangeV();
      std::uniform_real_distribution<double> U(a0, a1), V(b0, b1);
      std::vector<sampling::SurfaceQuery> queries(kSamplesPerFace);
      for (auto& q : queries) q = {true, 0, 0, U(random), V(random)};
      const double faceSize = boxDiagonal(model.points);
      for (const auto& [precision, relative] : {std::pair{Precision::Double, 1e-12}, std::pair{Precision::Float, 1e-6}}) {
        const double size = precision == Precision::Double ? faceSize : partSize;
        const auto result = session.evaluate(surface, {DeviceKind::Vulkan, precision, true}, queries);
        ASSERT_TRUE(result.report.gpu);
        double worstPoint = 0.0, worstDu = 0.0, worstDv = 0.0;
        for (size_t k = 0; k < queries.size(); ++k) {
          gp_Pnt p;
          gp_Vec du, dv;
          occt.bspline->D1(queries[k].u, queries[k].v, p, du, dv);
          worstPoint = std::max(worstPoint, glm::length(result.points[k].point - glm::dvec3(p.X(), p.Y(), p.Z())));
          worstDu = std::max(worstDu, glm::length(result.points[k].du - glm::dvec3(du.X(), du.Y(), du.Z())));
          worstDv = std::max(worstDv, glm::length(result.points[k].dv - glm::dvec3(dv.X(), dv.Y(), dv.Z())));
        }
        EXPECT_LE(worstPoint, relative * size) << (precision == Precision::Float ? "fp32" : "fp64");
        EXPECT_LE(worstDu, relative * size * derivativeScale(model.knotsU, model.family.order)) << (precision == Precision::Float ? "fp32" : "fp64");
        EXPECT_LE(worstDv, relative * size * derivativeScale(model.knotsV, model.orderV)) << (precision == Precision::Float ? "fp32" : "fp64");
      }
      ++faces;
    }
  }
  EXPECT_GE(faces, 26 + 8 + 3 + 1 + 1 + 1);
}

}  // namespace
}  // namespace shapespline::test
