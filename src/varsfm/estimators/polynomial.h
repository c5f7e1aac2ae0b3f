#pragma once
// Real roots of low-degree polynomials, for the seven-point solver's cubic (H&Z section 11.1.2)
// and the P3P solver's cubic and quadratics.
#include <vector>

namespace varsfm {

// Appends the real roots of a x^2 + b x + c (the linear case when a vanishes) to `roots`, with
// the cancellation-free pair of formulas. Returns the number appended.
int SolveQuadraticReal(double a, double b, double c, std::vector<double>* roots);

// Real roots of c3 x^3 + c2 x^2 + c1 x + c0 (falls back to the quadratic/linear case when the
// leading coefficients vanish), polished by Newton's method. Returns the number of roots.
int SolveCubicReal(double c3, double c2, double c1, double c0, std::vector<double>* roots);

}  // namespace varsfm
