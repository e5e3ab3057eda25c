#pragma once
// `Surface.project(points)`, `Curve.project(points)` and `Part.project(points)`: the closest points
// of an (n, 3) array on a projection tree (host/part/closest_points.h; docs/python.md "Closest
// points"), returned as NumPy arrays: in fp64 on the CPU, or with the search on the session's Vulkan
// device (`device`, `precision`, `require` as sample() takes them; a curve stays on the CPU).
#include <shapespline/part/projection_tree.h>

#include <pybind11/pybind11.h>

#include <optional>
#include <string>

namespace shapespline::python {

// A dict of point (n, 3), uv (n, 2) (a curve: t (n,)), distance (n,), and for surfaces and parts
// signed_distance (n,) and normal (n, 3); for parts face_ids (n,) int32. ValueError naming
// `points` for an array that is not (n, 3), empty, or has a non-finite value (its row), and naming
// `tolerance` for one that is not finite and > 0 (None: exact, part::ClosestPoints).
pybind11::dict projectPoints(const part::ProjectionTree& tree, pybind11::handle points, int threads,
                             std::optional<double> tolerance, bool part, const std::string& device = "cpu",
                             const std::string& precision = "double", bool require = false);

}  // namespace shapespline::python
