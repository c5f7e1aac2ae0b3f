#include "varsfm/ba/trust_region.h"

#include <cmath>

#include "varsfm/util/timer.h"

namespace varsfm::trust_region {

bool Linearise(SchurSystem* system, double* cost, SchurSolverSummary* summary) {
  const Timer t;
  const bool ok = system->Evaluate(/*linearise=*/true, cost);
  summary->seconds_linearise += t.Seconds();
  return ok;
}

bool StopBeforeStep(const SchurSolverOptions& options, const SchurSystem& system,
                    SchurSolverSummary* summary) {
  if (system.GradientMaxNorm() <= options.gradient_tolerance) {
    summary->converged = true;
    summary->message = "gradient tolerance reached";
    return true;
  }
  if (summary->successful_steps + summary->unsuccessful_steps >= options.max_iterations) {
    summary->message = "maximum number of iterations reached";
    return true;
  }
  return false;
}

bool StepBelowTolerance(const SchurSolverOptions& options, const SchurSystem& system,
                        double step_norm, SchurSolverSummary* summary) {
  if (step_norm >
      options.parameter_tolerance * (system.ParameterNorm() + options.parameter_tolerance))
    return false;
  summary->converged = true;
  summary->message = "parameter tolerance reached";
  return true;
}

StepTrial TryStep(SchurSystem* system, double cost, double model_decrease,
                  SchurSolverSummary* summary) {
  StepTrial trial;
  trial.new_cost = cost;
  if (!(model_decrease > 0.0) || !system->Step()) return trial;
  const Timer timer;
  const bool evaluated = system->Evaluate(/*linearise=*/false, &trial.new_cost);
  summary->seconds_residuals += timer.Seconds();
  if (evaluated && std::isfinite(trial.new_cost)) {
    trial.rho = (cost - trial.new_cost) / model_decrease;
    trial.accepted = trial.rho > kMinRelativeDecrease;
  }
  if (!trial.accepted) system->Restore();
  return trial;
}

bool AcceptStep(const SchurSolverOptions& options, const SchurSystem& system, double new_cost,
                double* cost, SchurSolverSummary* summary) {
  ++summary->successful_steps;
  const double relative_change = (*cost - new_cost) / *cost;
  *cost = new_cost;
  summary->final_cost = new_cost;
  summary->final_squared_norm = system.squared_norm();
  if (relative_change > options.function_tolerance) return false;
  summary->converged = true;
  summary->message = "function tolerance reached";
  return true;
}

bool RadiusBelowMinimum(double radius, SchurSolverSummary* summary) {
  if (radius >= kMinRadius) return false;
  summary->converged = true;
  summary->message = "trust region radius below its minimum";
  return true;
}

}  // namespace varsfm::trust_region
