#pragma once
// Internal to host/gpu: list samples into the SAMPLES records of shaders/layout.h (ListSample,
// including the knot-span lookups of knot-vector B-splines) and REAL bytes both ways.
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/curve_evaluator.h>
#include <shapespline/gpu/surface_evaluator.h>
#include <shapespline/shaders/layout.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace shapespline::gpu {

// (span, t) samples of a curve; throws std::out_of_range naming the sample outside the curve.
std::vector<layout::ListSampleD> curveListSamples(const GpuCurve& curve, std::span<const CurveSample> samples);
// Global parameters u of a curve (as Curve::evaluateAt).
std::vector<layout::ListSampleD> curveListSamplesAt(const GpuCurve& curve, std::span<const double> u);
// (patch, u, v) samples of a surface.
std::vector<layout::ListSampleD> surfaceListSamples(const GpuSurface& surface, std::span<const SurfaceSample> samples);
// The (patch, u, v) of global (U, V) (as Surface::evaluateAt).
std::vector<SurfaceSample> surfaceSamplesAt(const GpuSurface& surface, std::span<const std::pair<double, double>> uv);

// The records in REAL precision (ListSampleD as is, or ListSampleF).
std::vector<std::byte> packListSamples(const std::vector<layout::ListSampleD>& samples, Precision p);
// n REAL values at src into doubles.
void readReals(const std::byte* src, Precision p, size_t n, double* out);
// A list job's fields: `asked` within `all`, never empty (std::invalid_argument otherwise).
FieldMask listFields(FieldMask asked, FieldMask all);
// Point i of a read-back plane (3 doubles a point); 0 for an empty plane.
inline glm::dvec3 planePoint(const std::vector<double>& plane, size_t i) {
  return plane.empty() ? glm::dvec3(0.0) : glm::dvec3(plane[3 * i], plane[3 * i + 1], plane[3 * i + 2]);
}

}  // namespace shapespline::gpu
