#include "varsfm/ba/trust_region.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "varsfm/util/timer.h"

// Powell's dogleg (Nocedal & Wright, "Numerical Optimization", 2nd ed., sec. 4.1; Ceres'
// DoglegStrategy, traditional variant): the Gauss-Newton step with a small damping mu (raised
// tenfold while the reduced system is not positive definite), the Cauchy point along the scaled
// gradient, and between them the point of the path at the trust-region radius, all in the
// Jacobi-scaled norm |x|_D. A rejected step shrinks the radius and reuses both steps: no new
// factorisation, one residual evaluation.

namespace varsfm::trust_region {
namespace {

constexpr double kMinMu = 1e-8, kMaxMu = 1.0;
constexpr double kMaxExtrapolation = 4.0;

// The step a p + b u at the radius, p the Gauss-Newton step, u = D^-1 g: p when it lies inside,
// the steepest-descent step to the radius when the Cauchy point lies outside, else the point of
// the segment from the Cauchy point to p at the radius.
struct DoglegPoint {
  double a = 0.0;
  double b = 0.0;
};
DoglegPoint PointAtRadius(const SchurSystem::DoglegTerms& t, double radius) {
  const double gn_norm = std::sqrt(std::max(t.p_D_p, 0.0));
  const double u_norm = std::sqrt(std::max(t.g_u, 0.0));
  const double alpha = t.u_H_u > 0.0 ? t.g_u / t.u_H_u : std::numeric_limits<double>::max();
  DoglegPoint point;
  if (gn_norm <= radius) {
    point.a = 1.0;
  } else if (u_norm == 0.0 || alpha * u_norm >= radius) {
    point.b = u_norm > 0.0 ? -radius / u_norm : 0.0;
  } else {
    // q = -alpha u (the Cauchy point), p; |q + beta (p - q)|_D = radius, beta in [0, 1].
    const double qq = alpha * alpha * t.g_u, pq = -alpha * t.g_p, pp = t.p_D_p;
    const double c2 = pp - 2.0 * pq + qq, c1 = 2.0 * (pq - qq), c0 = qq - radius * radius;
    const double disc = std::max(c1 * c1 - 4.0 * c2 * c0, 0.0);
    const double beta = c2 > 0.0 ? (-c1 + std::sqrt(disc)) / (2.0 * c2) : 1.0;
    point.a = beta;
    point.b = -alpha * (1.0 - beta);
  }
  return point;
}

// An accepted step whose cost fell well beyond the model's prediction (rho > 1.2): the model's
// curvature along the step is too high (the Gauss-Newton term drops the residuals' own
// curvature, and a robust loss flattens), so the step stops short. The parabola through the cost
// at 0 and 1 with the exact slope g.delta there gives a longer step; one residual evaluation
// tries it, and it is kept only when the cost falls further (docs/mapper.md). Leaves the
// parameters at the step kept, its cost in `new_cost`; returns the step's factor (1: the step
// itself), none when a cost function fails.
std::optional<double> Extrapolate(SchurSystem* system, const SchurSystem::DoglegTerms& t,
                                  DoglegPoint point, double cost, double* new_cost,
                                  SchurSolverSummary* summary) {
  const double slope = point.a * t.g_p + point.b * t.g_u;  // d cost / d lambda at lambda = 0
  const double curvature = (*new_cost - cost) - slope;
  const double lambda =
      curvature > 0.0 ? std::min(-slope / (2.0 * curvature), kMaxExtrapolation) : kMaxExtrapolation;
  if (!(lambda > 1.5)) return 1.0;
  const Timer timer;
  double extrapolation = 1.0;
  double extrapolated_cost = *new_cost;
  system->Restore();
  system->SetDoglegStep(lambda * point.a, lambda * point.b);
  bool better = system->Step() && system->Evaluate(/*linearise=*/false, &extrapolated_cost) &&
                std::isfinite(extrapolated_cost) && extrapolated_cost < *new_cost;
  if (better) {
    *new_cost = extrapolated_cost;
    extrapolation = lambda;
  } else {  // back to the step itself
    system->Restore();
    system->SetDoglegStep(point.a, point.b);
    if (!system->Step() || !system->Evaluate(/*linearise=*/false, new_cost)) return std::nullopt;
  }
  summary->seconds_residuals += timer.Seconds();
  return extrapolation;
}

// The Gauss-Newton step with the least damping from mu up that makes the reduced system
// positive definite; false when none up to kMaxMu does.
bool SolveGaussNewtonStep(SchurSystem* system, double* mu, SchurSolverSummary* summary) {
  double model_decrease = 0.0, step_norm = 0.0;
  bool solved = false;
  Timer solve_timer;
  for (; *mu <= kMaxMu; *mu *= 10.0)
    if ((solved = system->SolveStep(*mu, &model_decrease, &step_norm))) break;
  summary->seconds_solve += solve_timer.Seconds();
  return solved;
}

}  // namespace

void Dogleg(const SchurSolverOptions& options, SchurSystem* system, double cost,
            SchurSolverSummary* summary) {
  double radius = options.initial_trust_region_radius;
  double mu = kMinMu;
  bool reuse = false;
  SchurSystem::DoglegTerms t;
  while (true) {
    if (StopBeforeStep(options, *system, summary)) return;
    if (!reuse) {
      if (!SolveGaussNewtonStep(system, &mu, summary)) {
        summary->message = "the reduced system is not positive definite";
        return;
      }
      t = system->KeepGaussNewtonStep(mu);
    }
    const DoglegPoint point = PointAtRadius(t, radius);
    const double a = point.a, b = point.b;
    // m(a p + b u) = a g.p + b g.u + (a^2 p'Hp + 2 a b u'Hp + b^2 u'Hu) / 2.
    const double pHp = -t.g_p - t.mu * t.p_D_p + t.p_rho;
    const double uHp = -t.g_u - t.mu * t.g_p + t.u_rho;
    const double model_decrease =
        -(a * t.g_p + b * t.g_u + 0.5 * (a * a * pHp + 2.0 * a * b * uHp + b * b * t.u_H_u));
    const double step_scaled =
        std::sqrt(std::max(a * a * t.p_D_p + 2.0 * a * b * t.g_p + b * b * t.g_u, 0.0));
    const double step_norm = system->SetDoglegStep(a, b);
    if (StepBelowTolerance(options, *system, step_norm, summary)) return;
    const StepTrial trial = TryStep(system, cost, model_decrease, summary);
    const bool accepted = trial.accepted;
    const double rho = trial.rho;
    double new_cost = trial.new_cost;
    double extrapolation = 1.0;
    if (accepted && rho > 1.2) {
      const std::optional<double> factor = Extrapolate(system, t, point, cost, &new_cost, summary);
      if (!factor) {
        summary->message = "a cost function failed";
        return;
      }
      extrapolation = *factor;
    }
    if (options.progress_to_stdout)
      std::printf(
          "%4d %s cost %.6e change %+.3e step %.3e rho %.3f radius %.3e (dogleg %.2f %.2e, "
          "x %.2f)\n",
          summary->successful_steps + summary->unsuccessful_steps, accepted ? "ok  " : "fail",
          accepted ? new_cost : cost, cost - new_cost, step_norm, rho, radius, a, b, extrapolation);
    if (!accepted) {
      ++summary->unsuccessful_steps;
      // Half the failed step's length, not only half the radius (Ceres): after a radius
      // increase the failed step is often the Gauss-Newton step well inside it, and halving the
      // radius alone tried a second step nearly as long (Nocedal & Wright, alg. 4.1 and
      // sec. 4.1, shrink from the step's length; docs/mapper.md).
      radius = 0.5 * std::min(radius, step_scaled);
      reuse = true;
      if (RadiusBelowMinimum(radius, summary)) return;
      continue;
    }
    if (rho < 0.25) radius *= 0.5;
    if (rho > 0.75) radius = std::max(radius, 3.0 * extrapolation * step_scaled);
    radius = std::min(radius, kMaxRadius);
    mu = std::max(kMinMu, mu / 5.0);
    reuse = false;
    if (AcceptStep(options, *system, new_cost, &cost, summary)) return;
    if (!Linearise(system, &cost, summary)) {
      summary->message = "a cost function failed";
      return;
    }
  }
}

}  // namespace varsfm::trust_region
