#pragma once
// The project's own bundle-adjustment solver: a trust region (Levenberg-Marquardt or Powell's
// dogleg) over the Schur complement of the points, the reduced camera system factorised dense or
// sparse. It runs the mapper's adjustments up to 5000 images (ChooseSolver, bundle_adjuster.cc);
// Ceres stays the reference (tests/ba) and the solver beyond (ITERATIVE_SCHUR).
//
// Why: Ceres' program evaluator and Schur eliminator are general (parameter-block indirection,
// manifold products through dynamic-size matrices, a dynamic f-block size once a problem mixes
// image blocks with a shared principal-point block), and a mapper runs one small solve per
// registered image. On the same problems it takes Ceres' iterations to Ceres' minimum in less
// time (docs/mapper.md, "Speed"; bench/ba_bench.cc, BM_SmallBundleAdjustment).
//
// The problem (Triggs et al., "Bundle adjustment - a modern synthesis", 2000):
//   minimise 1/2 sum_i rho_i(|r_i(x)|^2) over x,
// each residual block's residual and Jacobian corrected for its loss (Triggs' sec. 3.3, eq. 11).
// Every step solves the damped normal equations
//   (J^T J + mu D) delta = -J^T r,  D = diag(J^T J) clamped to [1e-6, 1e32],
// with the points (the blocks to eliminate) removed by the Schur complement (Triggs' sec. 6.1)
//   (S - W V^-1 W^T) delta_c = -g_c + W V^-1 g_p,   delta_p = V^-1 (-g_p - W^T delta_c),
// the reduced system Jacobi-scaled and factorised by Cholesky (schur_system.h). The steps are
// taken as Ceres' trust-region minimiser takes them (trust_region.h): Levenberg-Marquardt
// (Madsen, Nielsen & Tingleff, "Methods for non-linear least squares problems", 2004, sec. 3.2;
// mu = 1 / radius) or Powell's dogleg (Nocedal & Wright, "Numerical Optimization", 2nd ed.,
// sec. 4.1).
#include <string>
#include <vector>

#include <ceres/problem.h>

#include "varsfm/ba/least_squares_problem.h"

namespace varsfm {

struct SchurSolverOptions {
  int max_iterations = 100;  // successful and unsuccessful steps together, as Ceres counts
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double initial_trust_region_radius = 1e4;
  // Levenberg-Marquardt (Ceres' default), or Powell's dogleg: on a long sequence's final global
  // adjustment LM crawls along the weak directions of the per-image distortion and the
  // trajectory's bend, where the dogleg's Gauss-Newton steps go straight (docs/mapper.md).
  enum class TrustRegion { kLevenbergMarquardt, kDogleg };
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  // The reduced system's factorisation (cholesky.h): dense, or sparse (CHOLMOD's supernodal
  // LLT) for a large system with few blocks (a sequence's banded camera graph);
  // kAuto: sparse beyond 1500 columns, or beyond 300 when its blocks fill less than a quarter.
  enum class Factorization { kAuto, kDense, kSparse };
  Factorization factorization = Factorization::kAuto;
  // > 0: a sparse reduced system of at least this many blocks (images) is solved by
  // preconditioned conjugate gradients (reduced_camera_pcg.cc) to a relative residual of
  // iterative_tolerance, at most iterative_max_iterations of them; the trust region's model
  // takes the remaining residual into account.
  int iterative_min_blocks = 0;
  double iterative_tolerance = 1e-6;
  int iterative_max_iterations = 500;
  // Threads (<= 1: the calling thread only). The work is cut into a fixed number of parts and
  // summed in part order, so the result is the same bit for bit with any number of threads.
  int num_threads = 1;
  // One line per step on standard output, as Ceres' minimizer_progress_to_stdout prints them
  // (`varsfm --log-level trace`): where an adjustment spends its iterations.
  bool progress_to_stdout = false;
};

struct SchurSolverSummary {
  bool usable = false;     // the parameters hold a solution at least as good as the start
  bool converged = false;  // a tolerance was reached (not the iteration limit)
  int successful_steps = 0;
  int unsuccessful_steps = 0;
  double initial_cost = 0.0;  // 1/2 sum rho(|r|^2), as Ceres reports it
  double final_cost = 0.0;
  // sum |r|^2 without the loss, at the start and at the solution (for an RMS).
  double initial_squared_norm = 0.0;
  double final_squared_norm = 0.0;
  bool sparse = false;        // the reduced system was factorised sparse
  int reduced_columns = 0;    // its size
  double reduced_fill = 0.0;  // the fraction of its upper triangle its blocks cover
  std::string message;        // why it stopped
  // Where the time went (s): building the solver's view of the problem, residuals and
  // Jacobians with the normal equations' blocks, residuals only (trial steps), the reduced
  // system's assembly and solution.
  double seconds_setup = 0.0;
  double seconds_linearise = 0.0;
  double seconds_residuals = 0.0;
  double seconds_solve = 0.0;
  double seconds_factorise = 0.0;  // of which the reduced system's Cholesky factorisations
                                   // (or conjugate-gradient solves)
  bool iterative = false;          // the reduced system was solved by conjugate gradients
  int cg_iterations = 0;           // their iterations, all steps together
};

// Solves `problem` in place (its parameters change). `eliminate`: the parameter blocks removed by
// the Schur complement (the 3D points; each residual block may hold at most one of them, and only
// blocks of size 3 can be eliminated); every other variable block enters the reduced system, in
// the order of their addresses (the order Ceres gives a group of its elimination ordering).
SchurSolverSummary SolveWithSchurComplement(const SchurSolverOptions& options,
                                            const std::vector<double*>& eliminate,
                                            const LeastSquaresProblem& problem);
// The same on a ceres::Problem as it is built.
SchurSolverSummary SolveWithSchurComplement(const SchurSolverOptions& options,
                                            const std::vector<double*>& eliminate,
                                            ceres::Problem* problem);

}  // namespace varsfm
