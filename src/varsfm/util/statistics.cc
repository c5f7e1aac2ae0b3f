#include "varsfm/util/statistics.h"

#include <algorithm>
#include <cstddef>
#include <utility>

namespace varsfm {

double Quantile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(fraction * values.size()));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// floor(0.5 x size) is size / 2 exactly for every count a vector holds.
double Median(std::vector<double> values) { return Quantile(std::move(values), 0.5); }

}  // namespace varsfm
