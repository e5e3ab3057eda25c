#pragma once
// The statistics of a deviation report (`shapespline project --report`): per face and over all
// points, the count, min, max, mean and RMS of the distance, and its percentiles. Bounded memory
// for any number of points: the percentiles come from a histogram whose bins are 2^-10 wide
// relative to their value (the top 22 bits of the double), so a percentile is exact to 0.1%.
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace shapespline::part {

class DeviationStats {
 public:
  struct Summary {
    std::uint64_t count = 0;
    double min = 0.0, max = 0.0, mean = 0.0, rms = 0.0;
    std::vector<double> percentiles;  // at percentileLevels()
  };

  void add(int face, double distance);
  Summary overall() const { return summarise(all_); }
  // Per face id, ascending.
  std::map<int, Summary> perFace() const;
  // The levels reported: 50, 90, 95, 99, 99.9.
  static const std::vector<double>& percentileLevels();

  // The report as text: a header line, the overall row and one row per face (faceColumn false: a
  // surface or curve, the overall row alone).
  std::string text(bool faceColumn) const;

 private:
  struct Tally {
    std::uint64_t count = 0;
    double min = 0.0, max = 0.0, sum = 0.0, sumSquares = 0.0;
    std::unordered_map<std::uint32_t, std::uint64_t> bins;
    void add(double d);
  };
  static Summary summarise(const Tally& t);

  Tally all_;
  std::unordered_map<int, Tally> faces_;
};

}  // namespace shapespline::part
