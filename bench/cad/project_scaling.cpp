// How closest points scale with the size of the part (issue 55: points x log(patches), not points x
// patches). A sheet over [0, t]^2 is made of t x t unit faces, each a bicubic B-spline of 4 x 4
// knot intervals whose net waves in z (the wave runs on across the faces), for t = 1, 2, 4, ... up
// to --max-faces; N points, uniform over the sheet with z within +-0.1, are projected onto each
// part, best of REPS, on every core. The faces keep their size, so a point's neighbourhood looks
// the same in every row and only the part grows. Printed per part: faces, patches, tree cells, the
// tree's build time, microseconds per point, and that figure over log2(patches), which stays flat
// when the time grows with the logarithm (it would grow 4-fold per row if every patch were visited).
// Usage: shapespline_project_scaling_bench [--points N] [--reps N] [--max-faces N]
#include <shapespline/part/closest_points.h>
#include <shapespline/part/projection_tree.h>

#include "../../tests/part/wavy_face.h"
#include "bench_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace shapespline;

struct Options {
  int points = 100000, reps = 3, maxFaces = 4096;
};

Options parse(int argc, char** argv) {
  Options o;
  const auto parts = bench::parseArguments(argc, argv, [&](const std::string& a, const bench::OptionValue& value) {
    if (a == "--points") o.points = std::stoi(value());
    else if (a == "--reps") o.reps = std::stoi(value());
    else if (a == "--max-faces") o.maxFaces = std::stoi(value());
    else return false;
    return true;
  });
  if (!parts.empty()) throw std::invalid_argument("takes no part files (it makes its sheets): " + parts.front().string());
  if (o.points < 1 || o.reps < 1 || o.maxFaces < 1) throw std::invalid_argument("bad --points, --reps or --max-faces");
  return o;
}

// Face (a, b) of the sheet: [a, a + 1] x [b, b + 1], the wave running on across the faces.
Surface sheetFace(int a, int b) {
  return part::bicubicSheet({double(a), double(b)}, [](int, int, double x, double y) {
    return 0.05 * std::sin(9.0 * x + 4.0 * y) * std::cos(7.0 * y);
  });
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    std::vector<glm::dvec3> points(o.points);
    std::vector<part::FootPoint> feet(points.size());
    std::printf("closest points of %d points onto a sheet of t x t unit faces (16 bicubic patches each), best of %d\n",
                o.points, o.reps);
    std::printf("%7s %8s %8s %9s %10s %18s\n", "faces", "patches", "cells", "build s", "us/point", "us/point/log2(p)");
    for (int t = 1; t * t <= o.maxFaces; t *= 2) {
      std::mt19937_64 rng(11);
      std::uniform_real_distribution<double> across(0.0, double(t)), height(-0.1, 0.1);
      for (glm::dvec3& p : points) p = {across(rng), across(rng), height(rng)};
      std::vector<Surface> faces;
      faces.reserve(size_t(t) * t);
      for (int a = 0; a < t; ++a)
        for (int b = 0; b < t; ++b) faces.push_back(sheetFace(a, b));
      std::vector<part::ProjectionFace> listed;
      for (size_t k = 0; k < faces.size(); ++k) listed.push_back({&faces[k], int(k) + 1, false});
      std::optional<part::ProjectionTree> tree;
      const double build = bench::seconds([&] { tree.emplace(part::ProjectionTree::ofFaces(listed)); });
      const part::ClosestPoints closest(*tree);
      const double best = bench::bestSeconds(o.reps, [&] { closest.of(points, feet, false, 0); });
      const int patches = 16 * t * t;
      const double perPoint = 1e6 * best / o.points;
      std::printf("%7d %8d %8zu %9.3f %10.3f %18.4f\n", t * t, patches, tree->cells().size(), build, perPoint,
                  perPoint / std::log2(double(patches)));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shapespline_project_scaling_bench: %s\n", e.what());
    return 1;
  }
}
