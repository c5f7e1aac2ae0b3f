#pragma once
// The trust-region minimiser of the Schur solver (schur_solver.h), as Ceres' TrustRegionMinimizer
// runs it: each iteration tests the gradient and the iteration count, solves the Schur system for
// a step within the trust region, stops when the step is below the parameter tolerance, keeps it
// when the cost falls by more than a fraction of the model's decrease (Nocedal & Wright,
// "Numerical Optimization", 2nd ed., alg. 4.1), stops when that fall is below the function
// tolerance, and otherwise linearises again. The two ways of choosing the step:
//  - levenberg_marquardt.cc: the damped step, mu = 1 / radius (Madsen, Nielsen & Tingleff,
//    "Methods for non-linear least squares problems", 2004, sec. 3.2);
//  - dogleg.cc: Powell's dogleg between the Gauss-Newton step and the Cauchy point (Nocedal &
//    Wright, sec. 4.1).
// This file holds the tests and bookkeeping both share (Ceres' order and messages).
#include "varsfm/ba/schur_solver.h"
#include "varsfm/ba/schur_system.h"

namespace varsfm::trust_region {

// Ceres' defaults (solver.h): the radius's bounds, the least relative decrease a step must give.
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;

// Residuals, Jacobians and the normal equations' blocks at the current parameters into `system`,
// the cost into `cost`. False when a cost function fails.
bool Linearise(SchurSystem* system, double* cost, SchurSolverSummary* summary);

// Before a step: true when the gradient is small enough or the steps are used up.
bool StopBeforeStep(const SchurSolverOptions& options, const SchurSystem& system,
                    SchurSolverSummary* summary);

// True (converged) when the step is below the parameter tolerance.
bool StepBelowTolerance(const SchurSolverOptions& options, const SchurSystem& system,
                        double step_norm, SchurSolverSummary* summary);

// Takes the step set in `system` and evaluates the cost there; the step stays when it lowers the
// cost by more than kMinRelativeDecrease of the model's decrease, else it is undone.
struct StepTrial {
  bool accepted = false;
  double new_cost = 0.0;
  double rho = 0.0;  // actual over predicted decrease (0 when not evaluated)
};
StepTrial TryStep(SchurSystem* system, double cost, double model_decrease,
                  SchurSolverSummary* summary);

// An accepted step: the cost and summary move to it. True when the function tolerance stops.
bool AcceptStep(const SchurSolverOptions& options, const SchurSystem& system, double new_cost,
                double* cost, SchurSolverSummary* summary);

// A rejected step on a radius already below its minimum stops (converged).
bool RadiusBelowMinimum(double radius, SchurSolverSummary* summary);

// The minimisation from the parameters `system` was last linearised at (cost `cost`), until a
// test stops it; the summary's steps, costs, message and times are filled in.
void LevenbergMarquardt(const SchurSolverOptions& options, SchurSystem* system, double cost,
                        SchurSolverSummary* summary);
void Dogleg(const SchurSolverOptions& options, SchurSystem* system, double cost,
            SchurSolverSummary* summary);

}  // namespace varsfm::trust_region
