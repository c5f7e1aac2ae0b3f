#include "varsfm/ba/trust_region.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "varsfm/util/timer.h"

// Levenberg-Marquardt as Ceres' LEVENBERG_MARQUARDT strategy takes it (Madsen, Nielsen &
// Tingleff, "Methods for non-linear least squares problems", 2004, sec. 3.2): every step solves
// (J^T J + mu D) delta = -J^T r with mu = 1 / radius; an accepted step with gain ratio rho
// scales the radius by 1 / max(1/3, 1 - (2 rho - 1)^3), a rejected one divides it by 2, 4, 8...

namespace varsfm::trust_region {

void LevenbergMarquardt(const SchurSolverOptions& options, SchurSystem* system, double cost,
                        SchurSolverSummary* summary) {
  double radius = options.initial_trust_region_radius;
  double decrease_factor = 2.0;
  while (true) {
    if (StopBeforeStep(options, *system, summary)) return;
    const double mu = 1.0 / radius;
    double model_decrease = 0.0, step_norm = 0.0;
    StepTrial trial;
    trial.new_cost = cost;
    Timer solve_timer;
    const bool solved = system->SolveStep(mu, &model_decrease, &step_norm);
    summary->seconds_solve += solve_timer.Seconds();
    if (solved) {
      if (StepBelowTolerance(options, *system, step_norm, summary)) return;
      trial = TryStep(system, cost, model_decrease, summary);
      if (trial.accepted)
        radius = std::min(kMaxRadius,
                          radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * trial.rho - 1.0, 3)));
    }
    if (options.progress_to_stdout)
      std::printf("%4d %s cost %.6e change %+.3e step %.3e rho %.3f radius %.3e\n",
                  summary->successful_steps + summary->unsuccessful_steps,
                  trial.accepted ? "ok  " : "fail", trial.accepted ? trial.new_cost : cost,
                  cost - trial.new_cost, step_norm, trial.rho, radius);
    if (!trial.accepted) {
      ++summary->unsuccessful_steps;
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      if (RadiusBelowMinimum(radius, summary)) return;
      continue;
    }
    decrease_factor = 2.0;
    if (AcceptStep(options, *system, trial.new_cost, &cost, summary)) return;
    if (!Linearise(system, &cost, summary)) {
      summary->message = "a cost function failed";
      return;
    }
  }
}

}  // namespace varsfm::trust_region
