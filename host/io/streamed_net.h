#pragma once
// The values of a surface whose array files were left unread (io/model_json.h ModelArrays::outline),
// read a window at a time through the rules the full parse applies and kept nowhere: a shard with no
// items writes the job's identity (fingerprint, metadata) and no samples, so it needs these passes
// over the net but not the net itself, and runs in the same few MiB for a net of any size.
//
// The rules run in the order the full parse and Surface::create give them, so that the first error
// is the one a shard with items reports: each file's values finite (the parser's message, every
// file before any other rule), then α in (0,1], then the weights' rules. The α-EB vertex bound
// comes from the points' magnitude (core alphaEBVerticesSurelyFinite); a net it cannot clear needs
// the built surface's vertex-by-vertex check (StreamedNet::verticesShown false).
#include <shapespline/core/model.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/shard_info.h>

#include <cstddef>

namespace shapespline::io {

struct StreamedNet {
  double largestCoordinate = 0.0;  // the largest |coordinate| of the points
  AlphaTally alpha;                // what the job metadata keeps of α (α-EB)
  bool rational = false;           // the surface has weights
  bool verticesShown = true;       // α-EB: no vertex V leaves fp64 (false: not shown by the bound)
};

// Points per window: 1.5 MiB of points (and their weights).
inline constexpr size_t kStreamWindowPoints = size_t{1} << 16;

// Streams the values of `outline` (a surface parsed with ModelArrays::outline; `arrays` that parse's)
// through the value rules and into `fingerprint` (made with outlineCounts' α and weight counts).
// Throws ModelError for the first rule broken, as the full parse would name it.
StreamedNet streamSurfaceNet(const SurfaceModel& outline, const ModelArrays& arrays, SurfaceFingerprint& fingerprint,
                             size_t windowPoints = kStreamWindowPoints);

}  // namespace shapespline::io
