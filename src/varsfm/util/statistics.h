#pragma once
// Order statistics of samples, one definition for every module that summarises distances,
// depths or sharpness by their median.
#include <vector>

namespace varsfm {

// The value below which `fraction` of `values` lie: the element of rank
// min(size - 1, floor(fraction x size)), so fraction 1 gives the largest; 0 when there are none.
double Quantile(std::vector<double> values, double fraction);

// The element of rank size / 2 of `values` (for an even count the upper of the two middle
// values, so the result is always a sample); 0 when there are none.
double Median(std::vector<double> values);

}  // namespace varsfm
