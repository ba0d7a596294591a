#pragma once
// Summaries the benchmark tables print.
#include <algorithm>
#include <cmath>
#include <vector>

namespace roar::bench {

// The middle value (the upper of the two middle ones for an even count); NaN for none.
inline double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The arithmetic mean; NaN for none.
inline double mean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

}  // namespace roar::bench
