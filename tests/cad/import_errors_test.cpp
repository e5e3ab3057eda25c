// Bad parts (issue 32): a missing, empty, truncated, non-STEP or oversized file, a part without
// geometry: CadError naming the file and the entity, exit 2 from the CLI, and no output at all.
#include "test_parts.h"

#include <shapespline/cad/part_import.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Builder.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>

#include <cmath>

#include <cli/cli_runner.h>

#include <gtest/gtest.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Expects importPart to throw CadError for `part` with `entity` and a reason containing `reason`,
// and the output folder not to exist afterwards.
void expectRefused(const fs::path& part, const std::string& entity, const std::string& reason,
                   std::uint64_t maxBytes = std::uint64_t{1} << 30) {
  const fs::path out = part.parent_path() / "out";
  cad::ImportOptions options;
  options.maxFileBytes = maxBytes;
  try {
    cad::importPart(part, out, options);
    ADD_FAILURE() << part << " was imported";
  } catch (const cad::CadError& e) {
    EXPECT_EQ(e.file(), part.string());
    EXPECT_EQ(e.entity(), entity) << e.what();
    EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out)) << "output left behind for " << part;
}

TEST(ImportErrors, MissingEmptyOversizedAndWronglyNamedFiles) {
  ScratchDir dir("import_files");
  expectRefused(dir / "missing.step", "(file)", "no such file");
  writeText(dir / "empty.step", "");
  expectRefused(dir / "empty.step", "(file)", "the file is empty");
  writeStep(cylinder(), dir / "cylinder.step");
  expectRefused(dir / "cylinder.step", "(file)", "over the limit of 100", 100);
  fs::copy_file(dir / "cylinder.step", dir / "cylinder.txt");
  expectRefused(dir / "cylinder.txt", "(file)", "a part must be a STEP (.step, .stp) or IGES (.iges, .igs) file");
  fs::create_directory(dir / "folder.step");
  expectRefused(dir / "folder.step", "(file)", "not a regular file");
}

TEST(ImportErrors, TextThatIsNotStepOrIges) {
  ScratchDir dir("import_text");
  writeText(dir / "notes.step", "these are not the parts you are looking for\n");
  expectRefused(dir / "notes.step", "(file)", "not a readable STEP file");
  writeText(dir / "notes.iges", "these are not the parts you are looking for\n");
  // OCCT's IGES reader takes any text as a file of no entities: refused as a part without shapes.
  expectRefused(dir / "notes.iges", "(part)", "the IGES file holds no shape");
}

TEST(ImportErrors, TruncatedStepFile) {
  ScratchDir dir("import_truncated");
  writeStep(filletedBox(), dir / "whole.step");
  const std::string text = readText(dir / "whole.step");
  for (double fraction : {0.1, 0.5, 0.9}) {
    SCOPED_TRACE(fraction);
    writeText(dir / "cut.step", text.substr(0, static_cast<size_t>(fraction * text.size())));
    const fs::path out = dir / "out";
    try {
      cad::importPart(dir / "cut.step", out);
      // OCCT may recover the entities before the cut; then whatever it gives is whole models.
      EXPECT_TRUE(fs::exists(out / "part.json"));
      fs::remove_all(out);
    } catch (const cad::CadError& e) {
      EXPECT_EQ(e.file(), (dir / "cut.step").string());
      EXPECT_FALSE(fs::exists(out));
    }
  }
}

TEST(ImportErrors, PartWithoutFacesOrEdges) {
  ScratchDir dir("import_empty_part");
  TopoDS_Compound empty;
  BRep_Builder().MakeCompound(empty);
  try {
    writeStep(empty, dir / "empty_part.step");
  } catch (const std::runtime_error&) {
    GTEST_SKIP() << "OCCT does not write an empty compound";
  }
  expectRefused(dir / "empty_part.step", "(part)", "");
}

// A face beyond what a bspline model holds (degree 11 > order 10) is listed in part.json with the
// reason and named on stderr; the rest of the part is imported (exit 0). Alone, it is an error.
TEST(ImportCli, FacesThatDoNotConvertAreListedAndNamed) {
  ScratchDir dir("import_skipped");
  TColgp_Array2OfPnt points(1, 12, 1, 12);
  for (int i = 1; i <= 12; ++i)
    for (int j = 1; j <= 12; ++j) points(i, j) = gp_Pnt(i, j, std::sin(0.5 * i) * std::cos(0.4 * j));
  GeomAPI_PointsToBSplineSurface fit(points, 11, 11, GeomAbs_C2, 1e-3);
  ASSERT_TRUE(fit.IsDone());
  const Handle(Geom_Surface) surface(fit.Surface());
  ASSERT_EQ(fit.Surface()->UDegree(), 11);
  const TopoDS_Face high = BRepBuilderAPI_MakeFace(surface, 1e-7).Face();
  TopoDS_Compound both;
  BRep_Builder builder;
  builder.MakeCompound(both);
  builder.Add(both, high);
  builder.Add(both, cylinder());
  writeStep(both, dir / "both.step");
  CliResult r = runCli("import " + quote((dir / "both.step").string()) + " -o " + quote((dir / "both").string()), dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("degree 11 is above the largest order 10"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("not converted: see part.json"), std::string::npos) << r.out;
  const nlohmann::json manifest = nlohmann::json::parse(readText(dir / "both" / "part.json"));
  int skipped = 0, converted = 0;
  for (const auto& face : manifest.at("faces")) {
    if (face.at("model").is_null()) {
      ++skipped;
      EXPECT_NE(face.at("skipped").get<std::string>().find("degree 11"), std::string::npos) << face.dump();
    } else {
      ++converted;
    }
  }
  EXPECT_EQ(skipped, 1);
  EXPECT_EQ(converted, 3);
  // -q, as every subcommand takes it: no summary and no warnings; part.json still lists the face.
  r = runCli("import -q " + quote((dir / "both.step").string()) + " -o " + quote((dir / "quiet").string()), dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(nlohmann::json::parse(readText(dir / "quiet" / "part.json")).at("faces"), manifest.at("faces"));

  writeStep(high, dir / "high.step");
  r = runCli("import " + quote((dir / "high.step").string()) + " -o " + quote((dir / "high").string()), dir.path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("no face or edge could be converted"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "high"));
}

TEST(ImportCli, ImportsAPartAndRefusesBadOnesWithExitTwo) {
  ScratchDir dir("import_cli");
  writeStep(drilledPlate(), dir / "plate.step");
  CliResult r = runCli("import " + quote((dir / "plate.step").string()) + " -o " + quote((dir / "plate").string()),
                       dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("8 faces"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "plate" / "part.json"));
  EXPECT_TRUE(fs::exists(dir / "plate" / "face_0001.json"));

  writeText(dir / "bad.step", "not a step file");
  r = runCli("import " + quote((dir / "bad.step").string()) + " -o " + quote((dir / "bad").string()), dir.path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("PART"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.step"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a readable STEP file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));

  r = runCli("import " + quote((dir / "plate.step").string()) + " -o " + quote((dir / "tight").string()) +
                 " --trim-tolerance 0",
             dir.path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("--trim-tolerance"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "tight"));
}

// Open CASCADE is a plugin the CLI loads for `import` only (cad/part_plugin.h): the executable does
// not link it, so no other command pays for its libraries at start.
TEST(ImportCli, OnlyTheImportPluginLinksOpenCascade) {
  ScratchDir dir("import_links");
  const CliResult r = runShell("LD_TRACE_LOADED_OBJECTS=1 " + quote(SHAPESPLINE_CLI), dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("libc.so"), std::string::npos) << r.out;  // the listing is there
  EXPECT_EQ(r.out.find("libTK"), std::string::npos) << r.out;
}

// Without its plugin (a copied executable), `import` names the file it looked for (exit 3) and
// writes nothing; every other command still works.
TEST(ImportCli, AMissingPluginIsNamedAndNothingIsWritten) {
  ScratchDir dir("import_no_plugin");
  writeStep(cylinder(), dir / "part.step");
  const fs::path cli = dir / "shapespline";
  fs::copy_file(SHAPESPLINE_CLI, cli);
  auto run = [&](const std::string& args) { return runShell(quote(cli.string()) + " " + args, dir.path()); };
  CliResult r = run("import " + quote((dir / "part.step").string()) + " -o " + quote((dir / "part").string()));
  EXPECT_EQ(r.rc, 3) << r.err;
  EXPECT_NE(r.err.find("libshapespline-occt.so is not in any folder"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dir / "libshapespline-occt.so").string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "part"));
  r = run("--version");
  EXPECT_EQ(r.rc, 0) << r.err;
}

}  // namespace
}  // namespace shapespline::test
