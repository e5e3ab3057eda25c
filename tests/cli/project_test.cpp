// `shapespline project` (docs/cli.md "project"): a cloud in every input format gives the same feet,
// every output format carries the same numbers (read back with numpy), points sampled on a face
// come back at distance ~0 with their own (U, V), --report prints the statistics, and bad input
// exits 2 naming the file and the rule with nothing written. Shards (--shard K/N, auto, a pattern in
// -o) merge into the unsharded job's bytes in every format; a rerun shard that verifies is left as
// it is; shards that do not belong together are refused by merge. `--device vulkan` gives the CPU's
// feet (fp64 to 1e-12 of the part's size, fp32 within its bound); a curve stays on the CPU.
#include "cli_runner.h"
#include "handmade_part.h"
#include "output_checks.h"

#include <gtest/gtest.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

class Project : public ::testing::Test {
 protected:
  void SetUp() override { writeHandmadePart(dir_ / "part", {{2, 2}, {3, 1}}, true); }
  CliResult project(const std::string& points, const std::string& out, const std::string& extra = "") {
    return runCli("project " + quote((dir_ / points).string()) + " --onto " + quote((dir_ / "part/part.json").string()) +
                      " -o " + quote((dir_ / out).string()) + " " + extra,
                  dir_.path());
  }
  ScratchDir dir_{"project"};
};

// A cloud around the two faces (z from -0.5 to 1.6) in .npy, .f64, .csv and ASCII and binary PLY.
constexpr const char* kWriteClouds = R"(
import numpy as np, sys
rng = np.random.default_rng(7)
p = np.column_stack([rng.uniform(-0.2, 1.2, 800), rng.uniform(-0.2, 1.2, 800), rng.uniform(-0.5, 1.6, 800)])
np.save('cloud.npy', p)
p.astype('<f8').tofile('cloud.f64')
np.savetxt('cloud.csv', p, delimiter=',', fmt='%.17g', header='x,y,z', comments='')
with open('cloud_ascii.ply', 'w') as f:
    f.write('ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\nproperty double z\n'
            'property uchar red\nend_header\n' % len(p))
    for q in p: f.write('%.17g %.17g %.17g 7\n' % tuple(q))
rec = np.zeros(len(p), dtype=[('nx', '<f4'), ('x', '<f8'), ('y', '<f8'), ('z', '<f8')])
rec['x'], rec['y'], rec['z'] = p[:, 0], p[:, 1], p[:, 2]
with open('cloud_binary.ply', 'wb') as f:
    f.write(b'ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float nx\nproperty double x\n'
            b'property double y\nproperty double z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n' % len(p))
    f.write(rec.tobytes())
print('OK')
)";

TEST_F(Project, EveryCloudFormatGivesTheSameFeet) {
  expectPythonOk(dir_, kWriteClouds, {});
  for (const char* cloud : {"cloud.npy", "cloud.f64", "cloud.csv", "cloud_ascii.ply", "cloud_binary.ply"}) {
    const CliResult r = project(cloud, std::string(cloud) + ".f64", "-q");
    ASSERT_EQ(r.rc, 0) << cloud << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(readText(dir_ / (std::string(cloud) + ".f64")), readText(dir_ / "cloud.npy.f64")) << cloud;
  }
}

// The search on the Vulkan device: the same distances as the CPU's (fp64 to 1e-12 of the part's
// diagonal, fp32 to 64 ulps of it: tests/part/closest_points_gpu_test.cpp), the same faces where the
// CPU's foot is clearly nearer than any other face's, and the path named in the summary.
TEST_F(Project, VulkanSearchGivesTheCpuFeet) {
  REQUIRE_VULKAN();
  expectPythonOk(dir_, kWriteClouds, {});
  const CliResult cpu = project("cloud.npy", "cpu.npy", "");
  ASSERT_EQ(cpu.rc, 0) << cpu.err;
  EXPECT_TRUE(contains(cpu.out, "(cpu fp64)")) << cpu.out;
  for (const char* precision : {"double", "float"}) {
    const std::string out = std::string("gpu_") + precision + ".npy";
    const CliResult gpu = project("cloud.npy", out, std::string("--device vulkan --require-device --precision ") + precision);
    ASSERT_EQ(gpu.rc, 0) << gpu.err;
    EXPECT_TRUE(contains(gpu.out, precision == std::string("double") ? ", fp64" : ", fp32")) << gpu.out;
    expectPythonOk(dir_, R"(
import numpy as np, sys
a, b = np.load('cpu.npy'), np.load(sys.argv[1])
diag = np.linalg.norm(a['point'].max(axis=0) - a['point'].min(axis=0))  # at most the part's diagonal
bound = (1e-12 if sys.argv[2] == 'double' else 64 * 2.0**-24) * diag
gap = np.abs(a['distance'] - b['distance'])
assert gap.max() <= bound, (gap.max(), bound)
assert np.all(np.isfinite(b['point'])) and np.all(np.isfinite(b['normal']))
print('OK')
)", {out, precision});
  }
}

TEST_F(Project, OutputFormatsCarryTheSameNumbers) {
  expectPythonOk(dir_, kWriteClouds, {});
  for (const char* out : {"feet.npy", "feet.f64", "feet.csv", "feet.ply"}) {
    const CliResult r = project("cloud.npy", out, "--report");
    ASSERT_EQ(r.rc, 0) << out << "\n" << r.err;
    EXPECT_TRUE(contains(r.out, "projected 800 points onto 2 faces")) << r.out;
  }
  // The .npy by field; the .f64 its data; the CSV and PLY the same values; the feet lie on the
  // faces at their (U, V) within the faces' loops or on them, at the distance given.
  expectPythonOk(dir_, R"(
import numpy as np, json
a = np.load('feet.npy')
names = [n for n in a.dtype.names]
assert names == ['query', 'point', 'face', 'uv', 'distance', 'signed_distance', 'normal'], names
q = np.load('cloud.npy')
assert np.array_equal(a['query'], q)
d = np.linalg.norm(a['query'] - a['point'], axis=1)
assert np.allclose(d, a['distance'][:, 0], rtol=0, atol=1e-12), abs(d - a['distance'][:, 0]).max()
assert np.allclose(np.abs(a['signed_distance'][:, 0]), a['distance'][:, 0], rtol=0, atol=0)
assert np.allclose(np.linalg.norm(a['normal'], axis=1), 1, atol=1e-12)
assert set(np.unique(a['face'])) <= {0.0, 1.0}
assert np.isfinite(a.view('<f8')).all()
raw = np.fromfile('feet.f64', dtype=a.dtype)
assert raw.tobytes() == a.tobytes()
c = np.loadtxt('feet.csv', delimiter=',', skiprows=1)
assert np.array_equal(c, a.view('<f8').reshape(len(a), -1))
head = open('feet.csv').readline().strip()
assert head.startswith('query_x,query_y,query_z,point_x,point_y,point_z,face,u,v,distance,signed_distance'), head
with open('feet.ply', 'rb') as f:
    lines = []
    while True:
        line = f.readline().decode().strip(); lines.append(line)
        if line == 'end_header': break
    props = [l.split() for l in lines if l.startswith('property')]
    dt = np.dtype([(p[2], '<i4' if p[1] == 'int' else '<f8') for p in props])
    v = np.frombuffer(f.read(), dtype=dt)
assert 'element vertex 800' in lines
assert np.array_equal(np.column_stack([v['x'], v['y'], v['z']]), q)
assert np.array_equal(v['distance'], a['distance'][:, 0])
assert np.array_equal(v['face'], a['face'][:, 0].astype(int))
# Points straight above a face's middle (away from the hole) fall on that face, not its loops.
print('OK')
)",
                 {});
}

TEST_F(Project, PointsOnTheFacesComeBackWithTheirOwnParameters) {
  // Sample each face inside its loops (with its (U, V)), then project the points onto the part.
  for (int f = 0; f < 2; ++f) {
    const std::string face = "part/face_" + std::to_string(f) + ".json";
    const CliResult s = runCli("sample " + quote((dir_ / face).string()) + " --trim --grid 7x7 -q -o " +
                                   quote((dir_ / ("on_" + std::to_string(f) + ".npy")).string()),
                               dir_.path());
    ASSERT_EQ(s.rc, 0) << s.err;
  }
  expectPythonOk(dir_, R"(
import numpy as np
pts, uvs, faces = [], [], []
for f in range(2):
    a = np.load('on_%d.npy' % f)
    pts.append(a['point']); uvs.append(a['uv']); faces.append(np.full(len(a), f))
np.save('on.npy', np.concatenate(pts).astype('<f8'))
np.save('on_uv.npy', np.concatenate(uvs)); np.save('on_face.npy', np.concatenate(faces))
print('OK')
)",
                 {});
  const CliResult r = project("on.npy", "on_feet.npy", "-q");
  ASSERT_EQ(r.rc, 0) << r.err;
  expectPythonOk(dir_, R"(
import numpy as np
a = np.load('on_feet.npy'); uv = np.load('on_uv.npy'); face = np.load('on_face.npy')
q = a['query']; diag = np.linalg.norm(q.max(0) - q.min(0))
assert a['distance'].max() <= 1e-12 * diag, a['distance'].max()
assert np.array_equal(a['face'][:, 0], face)
assert np.abs(a['uv'] - uv).max() <= 1e-9, np.abs(a['uv'] - uv).max()
print('OK')
)",
                 {});
}

TEST_F(Project, ReportPrintsEachFaceAndTheWhole) {
  expectPythonOk(dir_, kWriteClouds, {});
  const CliResult r = project("cloud.npy", "feet.npy", "--report -q");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "points")) << r.out;
  EXPECT_TRUE(contains(r.out, "p99.9")) << r.out;
  EXPECT_TRUE(contains(r.out, "\nall ")) << r.out;
  EXPECT_TRUE(contains(r.out, "\n0 ")) << r.out;
  EXPECT_TRUE(contains(r.out, "\n1 ")) << r.out;
  writeText(dir_ / "report.txt", r.out);
  // The overall row: 800 points, and its max equals the largest distance in the file.
  expectPythonOk(dir_, R"(
import numpy as np, sys
a = np.load('feet.npy')
row = [l.split() for l in open('report.txt') if l.startswith('all ')][0]
assert int(row[1]) == 800, row
assert abs(float(row[3]) - a['distance'].max()) <= 1e-5 * a['distance'].max(), (row, a['distance'].max())
assert abs(float(row[2]) - a['distance'].min()) <= 1e-5 * a['distance'].max() + 1e-300, row
print('OK')
)",
                 {});
}

TEST_F(Project, ShardsMergeIntoTheUnshardedBytes) {
  expectPythonOk(dir_, kWriteClouds, {});
  for (const std::string ext : {".npy", ".f64", ".csv", ".ply"}) {
    ASSERT_EQ(project("cloud.npy", "whole" + ext, "-q").rc, 0);
    std::string shards;
    for (int k = 1; k <= 3; ++k) {
      const std::string name = "shard" + std::to_string(k) + ext;
      const CliResult r = project("cloud.npy", name, "--shard " + std::to_string(k) + "/3");
      ASSERT_EQ(r.rc, 0) << ext << "\n" << r.err;
      EXPECT_TRUE(contains(r.out, "(shard " + std::to_string(k) + "/3, points ")) << r.out;
      EXPECT_TRUE(fs::exists(dir_ / (name + ".shard.json"))) << name;
      shards += " " + quote((dir_ / name).string());
    }
    const CliResult m = runCli("merge -o " + quote((dir_ / ("merged" + ext)).string()) + shards, dir_.path());
    ASSERT_EQ(m.rc, 0) << ext << "\n" << m.err;
    EXPECT_EQ(readText(dir_ / ("merged" + ext)), readText(dir_ / ("whole" + ext))) << ext;
  }
  // Every cloud format starts a shard at the same point (PointCloudReader::skip).
  ASSERT_EQ(project("cloud.npy", "middle.f64", "-q --shard 2/3").rc, 0);
  for (const char* cloud : {"cloud.f64", "cloud.csv", "cloud_ascii.ply", "cloud_binary.ply"}) {
    const std::string out = std::string("middle_") + cloud + ".f64";
    ASSERT_EQ(project(cloud, out, "-q --shard 2/3").rc, 0) << cloud;
    EXPECT_EQ(readText(dir_ / out), readText(dir_ / "middle.f64")) << cloud;
  }
  // A rerun shard whose record verifies is left as it is.
  const CliResult again = project("cloud.npy", "shard2.npy", "--shard 2/3");
  EXPECT_EQ(again.rc, 0) << again.err;
  EXPECT_TRUE(contains(again.err, "nothing to do")) << again.err;
  // --shard auto from a Slurm job array, into a shard pattern, merged by the pattern.
  for (int k = 1; k <= 2; ++k) {
    const CliResult r = runShell("cd " + quote(dir_.path().string()) + " && env SLURM_ARRAY_TASK_ID=" + std::to_string(k) +
                                     " SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=2 " + quote(SHAPESPLINE_CLI) +
                                     " project cloud.npy --onto part/part.json -o 'auto-{shard}-of-{count}.csv' "
                                     "--shard auto -q",
                                 dir_.path());
    ASSERT_EQ(r.rc, 0) << r.err;
  }
  const CliResult m = runCli("merge -o merged_auto.csv 'auto-{shard}-of-{count}.csv'", dir_.path(), dir_.path());
  ASSERT_EQ(m.rc, 0) << m.err;
  EXPECT_EQ(readText(dir_ / "merged_auto.csv"), readText(dir_ / "whole.csv"));
}

TEST_F(Project, ShardsThatDoNotBelongTogetherAreNotMerged) {
  expectPythonOk(dir_, kWriteClouds, {});
  for (int k = 1; k <= 3; ++k)
    ASSERT_EQ(project("cloud.npy", "s" + std::to_string(k) + ".npy", "-q --shard " + std::to_string(k) + "/3").rc, 0);
  ASSERT_EQ(project("cloud.npy", "loose2.npy", "-q --shard 2/3 --tolerance 0.01").rc, 0);
  ASSERT_EQ(project("cloud.npy", "bare2.npy", "-q --shard 2/3").rc, 0);
  fs::remove(dir_ / "bare2.npy.shard.json");
  ASSERT_EQ(project("cloud.npy", "changed2.npy", "-q --shard 2/3").rc, 0);
  writeText(dir_ / "changed2.npy", readText(dir_ / "changed2.npy") + "x");
  const struct {
    std::string shards, named, rule;
  } cases[] = {
      {"s1.npy s3.npy", "SHARD[1]", "2 shards were given"},
      {"s2.npy s1.npy s3.npy", "SHARD[1]", "given as shard 1"},
      {"s1.npy loose2.npy s3.npy", "SHARD[2]", "another projection"},
      {"s1.npy bare2.npy s3.npy", "SHARD[2]", "no shard record"},
      {"s1.npy changed2.npy s3.npy", "SHARD[2]", "project the shard again"},
  };
  for (const auto& c : cases) {
    const CliResult r = runCli("merge -o merged.npy " + c.shards, dir_.path(), dir_.path());
    EXPECT_EQ(r.rc, 2) << c.shards << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.named)) << c.shards << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.rule)) << c.shards << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "merged.npy")) << c.shards;
  }
}

TEST_F(Project, BadInputExitsTwoNamingItAndWritesNothing) {
  expectPythonOk(dir_, R"(
import numpy as np
p = np.random.default_rng(1).uniform(0, 1, (50, 3))
bad = p.copy(); bad[17, 1] = np.nan; np.save('nan.npy', bad)
inf = p.copy(); inf[3, 2] = np.inf; inf.astype('<f8').tofile('inf.f64')
np.save('empty.npy', np.zeros((0, 3))); np.save('flat.npy', p[:, :2])
open('short.f64', 'wb').write(p.astype('<f8').tobytes()[:-8])
open('bad.csv', 'w').write('x,y,z\n1,2,3\n4,five,6\n')
open('bad.ply', 'w').write('ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n1 2\n3 4\n')
np.save('good.npy', p)
print('OK')
)",
                 {});
  fs::create_directories(dir_ / "missing");
  writePartManifest(dir_ / "missing", {"gone.json"});
  writeText(dir_ / "alpha.json",
            R"({"kind": "surface", "construction": "alpha_eb", "degree": 4, "lambda": 0, "closed": [false, false],
                "alpha": 0.5, "points": [[[0,0,0],[0,1,0],[0,2,0]],[[1,0,0],[1,1,1],[1,2,0]],[[2,0,0],[2,1,0],[2,2,0]]]})");
  struct Case {
    std::string args, named, rule;
  };
  const std::string part = quote((dir_ / "part/part.json").string());
  const std::vector<Case> cases = {
      {"nan.npy --onto " + part, "POINTS point 17", "finite"},
      {"inf.f64 --onto " + part, "POINTS point 3", "finite"},
      {"empty.npy --onto " + part, "POINTS", "no points"},
      {"flat.npy --onto " + part, "POINTS", "shape (N, 3)"},
      {"short.f64 --onto " + part, "POINTS", "whole x y z triples"},
      {"bad.csv --onto " + part, "POINTS line 3", "3 numbers"},
      {"bad.ply --onto " + part, "POINTS vertex", "property z"},
      {"good.npy --onto " + quote((dir_ / "missing/part.json").string()), "faces[0].model", "gone.json"},
      {"good.npy --onto alpha.json", "construction", "not polynomials"},
      {"absent.npy --onto " + part, "POINTS", "absent.npy"},
      {"good.npy --onto " + part + " --threads -1", "--threads", "must be in"},
      {"good.npy --onto " + part + " --tolerance 0", "--tolerance", "> 0"},
      {"good.npy --onto " + part + " --tolerance -1e-3", "--tolerance", "> 0"},
      {"good.npy --onto " + part + " --tolerance nan", "--tolerance", "finite"},
      {"good.npy --onto " + part + " --shard 4/3", "--shard", "K <= N"},
      {"good.npy --onto " + part + " --shard auto", "--shard", "auto"},
  };
  for (const Case& c : cases) {
    const CliResult r = runCli("project " + c.args + " -o out.npy", dir_.path(), dir_.path());
    EXPECT_EQ(r.rc, 2) << c.args << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.named)) << c.args << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.rule)) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.npy")) << c.args;
  }
  const CliResult ext = runCli("project " + quote((dir_ / "good.npy").string()) + " --onto " + part + " -o " +
                                    quote((dir_ / "out.obj").string()),
                                dir_.path());
  EXPECT_EQ(ext.rc, 2) << ext.err;
  EXPECT_TRUE(contains(ext.err, ".npy, .f64, .csv or .ply")) << ext.err;
  for (const std::string& e : dir_.entries()) EXPECT_EQ(e.find(".tmp-"), std::string::npos) << e;
}

}  // namespace
}  // namespace shapespline::test
