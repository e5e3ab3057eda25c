// `sample FACE.json --trim -o face.(glb|gltf|obj|stl|ply)` (docs/cad.md "Meshing a part") on a
// hand-made trimmed face: every mesh format is read back by a reader we did not write and holds the
// triangles the summary reports; bad options and faces exit 2 naming the option or the face, and
// leave nothing behind. The mesh's watertightness and deviation on real parts: tests/cad/.
#include "cli_runner.h"
#include "handmade_part.h"

#include <gtest/gtest.h>

#include <iterator>
#include <regex>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

class TrimmedMesh : public ::testing::Test {
 protected:
  void SetUp() override {
    writeText(dir_ / "face.json", handmadeFace(2, 2, 0.0));
    // The hole's corner (0.98, 0.5) lies outside the outer square: the loops cross.
    std::string crossing = handmadeFace(2, 2, 0.0);
    const std::string hole = "[[0.4,0.4],[0.6,0.4],[0.6,0.6],[0.4,0.6]]";
    crossing.replace(crossing.find(hole), hole.size(), "[[0.4,0.4],[0.98,0.5],[0.4,0.6]]");
    writeText(dir_ / "crossing.json", crossing);
  }
  CliResult sample(const std::string& model, const std::string& out, const std::string& extra = "") {
    return runCli("sample " + quote((dir_ / model).string()) + " --trim --device cpu -o " + quote((dir_ / out).string()) +
                      " " + extra,
                  dir_.path());
  }
  // The triangle count in "wrote X (1 faces, E edges, T triangles, ...)".
  static long reportedTriangles(const std::string& err) {
    std::smatch m;
    if (!std::regex_search(err, m, std::regex("(\\d+) triangles, (\\d+) vertices"))) return -1;
    return std::stol(m[1]);
  }
  ScratchDir dir_{"trimmed_mesh"};
};

TEST_F(TrimmedMesh, EveryFormatIsReadBackWithTheReportedTriangles) {
  CliResult r = sample("face.json", "face.glb");
  ASSERT_EQ(r.rc, 0) << r.err;
  const long triangles = reportedTriangles(r.err);
  ASSERT_GT(triangles, 100) << r.err;
  EXPECT_NE(r.err.find("1 faces, 2 edges"), std::string::npos) << r.err;

  if (const std::string why = gltfValidatorMissing(); why.empty()) {
    const GltfValidation v = validateGltf(dir_ / "face.glb");
    EXPECT_EQ(v.errors, 0) << v.report;
    EXPECT_EQ(v.warnings, 0) << v.report;
  } else {
    ADD_FAILURE() << why;
  }

  ASSERT_EQ(sample("face.json", "face.obj").rc, 0);
  if (const std::string why = assimpMissing(); why.empty()) {
    const ToolResult info = runTool("assimp info " + quote((dir_ / "face.obj").string()));
    EXPECT_NE(info.out.find("Faces:              " + std::to_string(triangles) + "\n"), std::string::npos) << info.out;
  } else {
    ADD_FAILURE() << why;
  }

  // STL: an 80-byte header, the count, 50 bytes a triangle; PLY: the element count (numpy reads both).
  ASSERT_EQ(sample("face.json", "face.stl").rc, 0);
  ASSERT_EQ(sample("face.json", "face.ply").rc, 0);
  if (const std::string why = pythonNumpyMissing(); why.empty()) {
    const ToolResult counts = runTool(
        std::string(kPython) + " -c \"import numpy as np, sys; s = open(sys.argv[1], 'rb').read(); "
        "n = int(np.frombuffer(s[80:84], '<u4')[0]); assert len(s) == 84 + 50 * n; "
        "h = open(sys.argv[2], 'rb').read().split(b'end_header')[0].decode(); "
        "f = [int(l.split()[2]) for l in h.splitlines() if l.startswith('element face')][0]; print(n, f)\" " +
        quote((dir_ / "face.stl").string()) + " " + quote((dir_ / "face.ply").string()));
    EXPECT_EQ(counts.out, std::to_string(triangles) + " " + std::to_string(triangles) + "\n");
  } else {
    ADD_FAILURE() << why;
  }
}

TEST_F(TrimmedMesh, BadOptionsAndCrossingLoopsExitTwoWithNothingWritten) {
  struct Case {
    std::string model, extra, named;
  };
  const Case cases[] = {
      {"face.json", "--deflection 0", "--deflection: must be a finite number > 0"},
      {"face.json", "--deflection -1e-3", "--deflection: must be a finite number > 0"},
      {"face.json", "--deflection nan", "--deflection: must be a finite number > 0"},
      {"face.json", "--relative-deflection inf", "--relative-deflection: must be a finite number > 0"},
      {"face.json", "--deflection 1e-3 --relative-deflection 1e-3", "--deflection: give --deflection"},
      {"face.json", "--angle 3.5", "--angle: must be below pi"},
      {"face.json", "--max-triangles 0", "--max-triangles: must be > 0"},
      {"face.json", "--deflection 1e-9 --max-triangles 5000", "needs more than the budget of 5000 triangles"},
      {"face.json", "--grid 8", "--grid: a trimmed mesh is made to a deflection"},
      {"face.json", "--shard 1/2", "--shard"},
      {"face.json", "--derivatives", "--derivatives"},
      {"crossing.json", "", "its trim loops cross each other"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.extra + " " + c.model);
    const CliResult r = sample(c.model, "out.glb", c.extra);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.glb"));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_.path()), fs::directory_iterator{}), 2) << "a file was left";
  }
  // Mesh options on a point cloud are refused too.
  const CliResult r = sample("face.json", "cloud.npy", "--grid 8 --deflection 1e-3");
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_NE(r.err.find("--deflection: applies to the mesh"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "cloud.npy"));
}

// `--device auto` meshes on the CPU (part/face_evaluator.h meshDeviceRequest: the mesher's many
// small lists cost a device submission each); `--device vulkan` is taken at its word.
TEST_F(TrimmedMesh, AutoMeshesOnTheCpu) {
  const CliResult r = runCli("sample " + quote((dir_ / "face.json").string()) + " --trim -o " +
                                 quote((dir_ / "auto.glb").string()),
                             dir_.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.err.find(", cpu fp64)"), std::string::npos) << r.err;
}

// A part whose manifest has no coedges (written before they existed, or by hand) cannot be welded:
// exit 2 naming the face's key.
TEST_F(TrimmedMesh, APartWithoutCoedgesIsRefusedByKey) {
  writeHandmadePart(dir_ / "part", {{1, 1}});
  const CliResult r = runCli("sample " + quote((dir_ / "part" / "part.json").string()) + " --device cpu -o " +
                                 quote((dir_ / "part.glb").string()),
                             dir_.path());
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_NE(r.err.find("faces[0].coedges"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "part.glb"));
}

}  // namespace
}  // namespace shapespline::test
