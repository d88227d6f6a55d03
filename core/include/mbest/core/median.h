// Middle values: of measured radii, and of timings.
#pragma once

#include <algorithm>
#include <vector>

namespace mbest {

// The middle value of `values` (of two middle ones, the upper): always one of the values,
// e.g. a radius that was measured; 0 when there are none. Linear time.
template <class T>
T middle_value(std::vector<T> values) {
  if (values.empty()) return T(0);
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  return values[mid];
}

// Median of `values`: the middle one, or the mean of the two middle ones for an even
// count; 0 when there are none. Linear time.
template <class T>
T median(std::vector<T> values) {
  if (values.empty()) return T(0);
  const size_t n = values.size(), mid = n / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  if (n % 2) return values[mid];
  const T lower = *std::max_element(values.begin(), values.begin() + static_cast<long>(mid));
  return (lower + values[mid]) / 2;
}

}  // namespace mbest
