#pragma once
// A surface whose points are a .npy file (io/model_json.h ModelArrays::outline), sampled in bands of
// patch rows while the rest of its net is still being read: the first samples of a big net come
// after its first rows, not after all of them, and the net is never held whole (a band and the
// window being read). Every value still goes through the value rules, the job fingerprint and the
// metadata's α tally, in file order, as io/streamed_net.h streams them for a shard with no items.
//
// A band is core Surface::bandOf of its rows: the same bits as the whole surface's patchRows. The
// rules are applied as the values arrive, so the first error found need not be the one the full
// parse names first (that parse checks every file's values before any other rule): a caller that
// must name the whole job's error runs the full parse when this throws.
//
// A curve whose points are a .npy file streams the same way (streamCurveSpans): its points are the
// rows (one point each), its bands runs of spans (core Curve::bandOf).
#include <shapespline/core/curve.h>
#include <shapespline/core/diagnostics.h>
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/streamed_net.h>

#include <cstddef>
#include <functional>

namespace shapespline::io {

// Called in order with each band: the surface of patch rows first..last (whole-net indices).
using BandSink = std::function<void(const Surface& band, int first, int last)>;

struct BandSizes {
  int firstRows = 1;          // patch rows of the first band (the first samples come after it)
  size_t maxBytes = 16 << 20;  // of a band's net at most (bands double from firstRows up to it)
};

// Whether streamSurfaceBands can take this outline: uniform-span families (not knot vectors), no
// weights, its points a file.
bool bandsCanStream(const SurfaceModel& outline, const ModelArrays& arrays);

// Streams the outline's values (as streamSurfaceNet) and hands `sink` the bands that cover patch
// rows `rows` (none when rows.first > rows.last) as soon as their rows are read and checked. The
// returned StreamedNet::verticesShown is true when every vertex was either in a band (each checks
// its own) or cleared by the bound from the whole net. `warnings` (optional) sees every point and
// α for the precision warnings. Throws ModelError for a value that breaks a rule (not necessarily
// the full parse's first, above) and whatever `sink` throws.
StreamedNet streamSurfaceBands(const SurfaceModel& outline, const ModelArrays& arrays,
                               NetFingerprint& fingerprint, SpanRange rows, const BandSink& sink,
                               BandSizes sizes = {}, size_t windowPoints = kStreamWindowPoints,
                               SurfaceWarningScan* warnings = nullptr);

// A curve whose points (and α) are .npy files, sampled in bands of spans the same way: the band
// machinery above with a curve's points for rows (core Curve::bandOf: the same bits as the whole
// curve's spans). Called in order with each band that meets the spans asked for.
using CurveBandSink = std::function<void(const Curve& band, int first, int last)>;

// Whether streamCurveSpans can take this outline: uniform or span-knot families (not knot
// vectors), no weights, its points a file.
bool curveSpansCanStream(const CurveModel& outline, const ModelArrays& arrays);

// Streams the outline's values through the value rules, `fingerprint`, the α tally and `warnings`
// (optional: the precision warnings), and hands
// `sink` the bands that cover spans `spans` (none when spans.first > spans.last). Bands are built
// over every span (the rest only checked), so each α-EB vertex is checked by its band and the
// returned verticesShown is true. Throws ModelError for a value that breaks a rule (not
// necessarily the full parse's first: a caller that must name it runs the full parse) and
// whatever `sink` throws.
StreamedNet streamCurveSpans(const CurveModel& outline, const ModelArrays& arrays, NetFingerprint& fingerprint,
                             SpanRange spans, const CurveBandSink& sink, BandSizes sizes = {},
                             size_t windowPoints = kStreamWindowPoints, CurveWarningScan* warnings = nullptr);

}  // namespace shapespline::io
