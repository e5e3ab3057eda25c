#pragma once
// The connectivity of welded OBJ and PLY files (io/welded_mesh.h), written by the writers and by
// `merge` through these functions alone, so that a merged file is the unsharded one byte for byte.
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/welded_mesh.h>

#include <string>

namespace shapespline::io {

// OBJ lines per welded vertex: v, vt, vn for surfaces; v for curves.
inline int objLinesPerVertex(bool surface) { return surface ? 3 : 1; }
// OBJ: the `f v/vt/vn ...` triangles (surfaces) or one `l` polyline (curves; a closed whole curve
// ends at its first vertex), 1-based absolute indices.
void writeObjConnectivity(AtomicFile& out, const WeldedNumbering& numbering, bool reversed);

// PLY: the element lines of the connectivity, "element face N" + its list property (surfaces) or
// "element edge N" + vertex1/vertex2 (curves: the polyline's consecutive pairs).
std::string plyConnectivityHeader(const WeldedNumbering& numbering);
uint64_t plyConnectivityRecords(const WeldedNumbering& numbering);
void writePlyConnectivity(AtomicFile& out, const WeldedNumbering& numbering, bool reversed);

}  // namespace shapespline::io
