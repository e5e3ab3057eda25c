// Connectivity of welded OBJ and PLY files (io/welded_formats.h).
#include <shapespline/io/number_text.h>
#include <shapespline/io/welded_formats.h>

#include <cstdint>
#include <cstring>

namespace shapespline::io {

void writeObjConnectivity(AtomicFile& out, const WeldedNumbering& numbering, bool reversed) {
  if (numbering.grid().curve()) {
    if (numbering.polylineLength() == 0) return;
    out.write("l", 1);
    numbering.forEachPolylinePoint([&](uint64_t i) {
      char* s = out.space(32);
      char* e = s;
      *e++ = ' ';
      e = writeInteger(e, static_cast<long long>(i + 1));
      out.advance(static_cast<size_t>(e - s));
    });
    out.write("\n", 1);
    return;
  }
  numbering.forEachTriangle(reversed, [&](uint64_t i0, uint64_t i1, uint64_t i2) {
    char* s = out.space(128);
    char* e = s;
    *e++ = 'f';
    for (uint64_t i : {i0, i1, i2}) {
      *e++ = ' ';
      char* start = e;
      e = writeInteger(e, static_cast<long long>(i + 1));
      const size_t n = static_cast<size_t>(e - start);
      for (int copy = 0; copy < 2; ++copy) {  // v/vt/vn share one index
        *e++ = '/';
        std::memcpy(e, start, n);
        e += n;
      }
    }
    *e++ = '\n';
    out.advance(static_cast<size_t>(e - s));
  });
}

uint64_t plyConnectivityRecords(const WeldedNumbering& numbering) {
  if (!numbering.grid().curve()) return numbering.triangleCount();
  const uint64_t n = numbering.polylineLength();
  return n == 0 ? 0 : n - 1;
}

std::string plyConnectivityHeader(const WeldedNumbering& numbering) {
  const std::string n = std::to_string(plyConnectivityRecords(numbering));
  return numbering.grid().curve() ? "element edge " + n + "\nproperty uint vertex1\nproperty uint vertex2\n"
                                  : "element face " + n + "\nproperty list uchar uint vertex_indices\n";
}

void writePlyConnectivity(AtomicFile& out, const WeldedNumbering& numbering, bool reversed) {
  // Callers refuse files of 2^32 vertices or more, so every index fits.
  if (numbering.grid().curve()) {
    bool first = true;
    uint32_t previous = 0;
    numbering.forEachPolylinePoint([&](uint64_t i) {
      const uint32_t index = static_cast<uint32_t>(i);
      if (!first) {
        const uint32_t edge[2] = {previous, index};
        out.write(edge, sizeof edge);
      }
      first = false;
      previous = index;
    });
    return;
  }
  numbering.forEachTriangle(reversed, [&](uint64_t i0, uint64_t i1, uint64_t i2) {
    char* e = out.space(13);
    e[0] = 3;
    const uint32_t t[3] = {static_cast<uint32_t>(i0), static_cast<uint32_t>(i1), static_cast<uint32_t>(i2)};
    std::memcpy(e + 1, t, 12);
    out.advance(13);
  });
}

}  // namespace shapespline::io
