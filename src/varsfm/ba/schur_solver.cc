#include "varsfm/ba/schur_solver.h"

#include "varsfm/ba/schur_system.h"
#include "varsfm/ba/trust_region.h"
#include "varsfm/util/timer.h"

namespace varsfm {

SchurSolverSummary SolveWithSchurComplement(const SchurSolverOptions& options,
                                            const std::vector<double*>& eliminate,
                                            ceres::Problem* problem) {
  return SolveWithSchurComplement(options, eliminate, LeastSquaresProblem::ViewOf(problem));
}

SchurSolverSummary SolveWithSchurComplement(const SchurSolverOptions& options,
                                            const std::vector<double*>& eliminate,
                                            const LeastSquaresProblem& problem) {
  SchurSolverSummary summary;
  Timer timer;
  SchurSystem system(eliminate, options, problem);
  summary.seconds_setup = timer.Seconds();
  if (!system.ok()) {
    summary.message = "a residual block uses a parameter block the problem does not have";
    return summary;
  }
  summary.sparse = system.sparse();
  summary.reduced_columns = system.num_columns();
  summary.reduced_fill = system.fill();
  double cost = 0.0;
  if (!trust_region::Linearise(&system, &cost, &summary)) {
    summary.message = "a cost function failed at the initial parameters";
    return summary;
  }
  summary.usable = true;
  summary.initial_cost = summary.final_cost = cost;
  summary.initial_squared_norm = summary.final_squared_norm = system.squared_norm();
  if (options.trust_region == SchurSolverOptions::TrustRegion::kDogleg)
    trust_region::Dogleg(options, &system, cost, &summary);
  else
    trust_region::LevenbergMarquardt(options, &system, cost, &summary);
  summary.seconds_factorise = system.seconds_factorise();
  summary.iterative = system.iterative();
  summary.cg_iterations = system.cg_iterations();
  return summary;
}

}  // namespace varsfm
