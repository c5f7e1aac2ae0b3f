#pragma once
// Real roots of low-degree polynomials, for the seven-point solver's cubic (H&Z section 11.1.2).
#include <vector>

namespace varsfm {

// Real roots of c3 x^3 + c2 x^2 + c1 x + c0 (falls back to the quadratic/linear case when the
// leading coefficients vanish), polished by Newton's method. Returns the number of roots.
int SolveCubicReal(double c3, double c2, double c1, double c0, std::vector<double>* roots);

}  // namespace varsfm
