#include "varsfm/estimators/polynomial.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace varsfm {

int SolveQuadraticReal(double a, double b, double c, std::vector<double>* roots) {
  const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
  if (scale == 0) return 0;
  if (std::abs(a) <= 1e-14 * scale) {
    if (b == 0) return 0;
    roots->push_back(-c / b);
    return 1;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return 0;
  // The numerically stable pair of formulas (Numerical Recipes 5.6).
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  if (q == 0) {
    roots->push_back(0.0);
    return 1;
  }
  roots->push_back(q / a);
  roots->push_back(c / q);
  return 2;
}

int SolveCubicReal(double c3, double c2, double c1, double c0, std::vector<double>* roots) {
  roots->clear();
  const double scale = std::max({std::abs(c3), std::abs(c2), std::abs(c1), std::abs(c0)});
  if (scale == 0) return 0;
  if (std::abs(c3) <= 1e-14 * scale) return SolveQuadraticReal(c2, c1, c0, roots);
  // Depressed cubic t^3 + p t + q with x = t - a/3 (Cardano), trigonometric form for three
  // real roots.
  const double a = c2 / c3, b = c1 / c3, c = c0 / c3;
  const double p = b - a * a / 3.0;
  const double q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
  const double disc = q * q / 4.0 + p * p * p / 27.0;
  if (disc > 0) {
    const double s = std::sqrt(disc);
    roots->push_back(std::cbrt(-q / 2.0 + s) + std::cbrt(-q / 2.0 - s) - a / 3.0);
  } else if (p == 0) {
    roots->push_back(-a / 3.0);
  } else {
    const double r = 2.0 * std::sqrt(-p / 3.0);
    const double arg = std::clamp(3.0 * q / (p * r), -1.0, 1.0);
    const double phi = std::acos(arg) / 3.0;
    for (int k = 0; k < 3; ++k)
      roots->push_back(r * std::cos(phi - 2.0 * std::numbers::pi * k / 3.0) - a / 3.0);
  }
  // Newton polishing: Cardano loses digits when roots are close or coefficients badly scaled.
  for (double& x : *roots) {
    for (int iter = 0; iter < 3; ++iter) {
      const double f = ((x + a) * x + b) * x + c;
      const double df = (3 * x + 2 * a) * x + b;
      if (df == 0) break;
      x -= f / df;
    }
  }
  return static_cast<int>(roots->size());
}

}  // namespace varsfm
