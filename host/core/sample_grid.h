#pragma once
// Regular sample grids and the chunk type every sampler (CPU fp64, Vulkan fp32/fp64) delivers.
//
// A grid places S samples on each curve span (t_s = s/(S-1), both ends included) or Su x Sv samples
// on each surface patch (u_a = a/(Su-1), v_b = b/(Sv-1)), so neighbouring spans/patches repeat
// their shared edge samples: every span/patch is a self-contained block, which is what lets a job be
// split into chunks and shards of whole items and lets a mesh writer emit each patch on its own.
// Items are spans (curves) or patches (surfaces, row-major over the patch range, u outer).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace shapespline {

enum class Field : uint32_t { Point = 0, D1, D2, Du, Dv, Duu, Duv, Dvv, Normal, Count };
inline constexpr int kFieldCount = static_cast<int>(Field::Count);
using FieldMask = uint32_t;
constexpr FieldMask fieldBit(Field f) { return 1u << static_cast<uint32_t>(f); }

enum class Precision { Float, Double };

struct GridSpec {
  int samplesU = 2;        // per span (curves) or per patch along u (surfaces); >= 2
  int samplesV = 1;        // per patch along v (surfaces); 1 for curves
  size_t firstItem = 0;    // first span/patch (index into the model's item list, 0-based)
  size_t itemCount = 0;    // 0 = all items from firstItem on
  size_t pointsPerItem() const { return static_cast<size_t>(samplesU) * static_cast<size_t>(samplesV); }
};

// One block of consecutive items. Each requested field is a tightly packed xyz plane
// (3 values per point, point index = item-in-chunk * pointsPerItem + a * samplesV + b).
struct GridChunk {
  size_t firstItem = 0;
  size_t itemCount = 0;
  size_t pointsPerItem = 0;
  Precision precision = Precision::Double;
  std::array<const void*, kFieldCount> planes{};  // nullptr where the field was not requested

  size_t pointCount() const { return itemCount * pointsPerItem; }
  bool has(Field f) const { return planes[static_cast<size_t>(f)] != nullptr; }
  double coord(Field f, size_t point, int axis) const {
    const void* p = planes[static_cast<size_t>(f)];
    const size_t i = point * 3 + static_cast<size_t>(axis);
    return precision == Precision::Double ? static_cast<const double*>(p)[i]
                                          : static_cast<double>(static_cast<const float*>(p)[i]);
  }
};

// Receives chunks in increasing item order; the data is valid only during the call.
using ChunkConsumer = std::function<void(const GridChunk&)>;

}  // namespace shapespline
