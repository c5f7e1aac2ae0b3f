#pragma once
// Levenberg-Marquardt with the Schur complement of the points, for bundle-adjustment problems:
// the project's own solver (the mapper's up to 5000 images; the file keeps its first name, the
// reduced system is factorised dense or sparse). It solves a ceres::Problem as it is built (cost
// functions, loss functions and manifolds through their public interfaces), or the same blocks
// handed over without one (SchurProblem), so the model is defined once and either solver runs
// it; Ceres stays the reference (tests/ba) and the solver beyond 5000 images (ITERATIVE_SCHUR).
//
// Why: Ceres' program evaluator and Schur eliminator are general (parameter-block indirection,
// manifold products through dynamic-size matrices, a dynamic f-block size once a problem mixes
// image blocks with a shared principal-point block), and a mapper runs one small solve per
// registered image. Measured against Ceres' DENSE_SCHUR on the same problems, same iterations
// and minimum: fountain-P11's final global adjustment 0.78 s against 2.06 s; the figures are in
// ChooseSolver (bundle_adjuster.cc) and bench/ba_bench.cc (BM_SmallBundleAdjustment).
//
// The algorithm is Ceres' LEVENBERG_MARQUARDT trust region (Madsen, Nielsen & Tingleff,
// "Methods for non-linear least squares problems", 2004, sec. 3.2; Triggs et al., "Bundle
// adjustment - a modern synthesis", 2000, sec. 6.1 for the Schur complement and sec. 3.3 for the
// robust-loss correction):
//   minimise 1/2 sum_i rho_i(|r_i(x)|^2) over x, every step solving
//   (J^T J + mu D) delta = -J^T r,  D = diag(J^T J) clamped to [1e-6, 1e32],  mu = 1 / radius,
// with the residuals and Jacobians of each block corrected for its loss (Triggs' eq. 11), the
// points (the blocks to eliminate) removed by the Schur complement
//   (S - W V^-1 W^T) delta_c = -g_c + W V^-1 g_p,   delta_p = V^-1 (-g_p - W^T delta_c),
// the reduced system Jacobi-scaled and factorised by Cholesky, and the radius updated from
// the ratio of actual to predicted decrease as Ceres does (x 1 / max(1/3, 1 - (2 rho - 1)^3) on
// success, / 2, 4, 8... on failure).
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

namespace varsfm {

struct DenseSchurOptions {
  int max_iterations = 100;  // successful and unsuccessful steps together, as Ceres counts
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double initial_trust_region_radius = 1e4;
  // Levenberg-Marquardt (Ceres' default), or Powell's dogleg: on a long sequence's final global
  // adjustment (bench/scale, 1000 images) LM crawled along the weak directions of the per-image
  // distortion and the trajectory's bend, where the dogleg's Gauss-Newton steps go straight.
  enum class Strategy { kLevenbergMarquardt, kDogleg };
  Strategy strategy = Strategy::kLevenbergMarquardt;
  // The reduced system's factorisation (cholesky.h): dense, or sparse (CHOLMOD's supernodal
  // LLT) for a large system with few blocks (a sequence's banded camera graph);
  // kAuto: sparse beyond 1500 columns, or beyond 300 when its blocks fill less than a quarter.
  enum class Factorization { kAuto, kDense, kSparse };
  Factorization factorization = Factorization::kAuto;
  // Threads (<= 1: the calling thread only). The work is cut into a fixed number of parts and
  // summed in part order, so the result is the same bit for bit with any number of threads.
  int num_threads = 1;
  // One line per step on standard output, as Ceres' minimizer_progress_to_stdout prints them
  // (`varsfm --log-level trace`): where an adjustment spends its iterations.
  bool progress_to_stdout = false;
};

struct DenseSchurSummary {
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
};

// The problem as the solver sees it: parameter blocks (a manifold, or held whole) and residual
// blocks over them, nothing owned. The mapper builds it directly instead of a ceres::Problem
// (a hash map per block, checks and a heap object per residual, its destruction): the local
// adjustments of a 200-image street sequence 9.5 -> 6.0 s, the same model bit for bit. Every
// block a residual uses must be added once, before or after its residuals.
class SchurProblem {
 public:
  struct ParameterBlock {
    double* x = nullptr;
    int size = 0;
    const ceres::Manifold* manifold = nullptr;  // null: Euclidean
    bool constant = false;
  };
  struct ResidualBlock {
    const ceres::CostFunction* cost = nullptr;
    const ceres::LossFunction* loss = nullptr;  // null: squared loss
    int begin = 0;                              // its blocks: parameters()[begin, begin + count)
    int count = 0;
  };

  void Reserve(size_t num_parameter_blocks, size_t num_residual_blocks, size_t num_parameters);
  void AddParameterBlock(double* x, int size, const ceres::Manifold* manifold = nullptr,
                         bool constant = false);
  void AddResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        const double* const* blocks, int count);

  const std::vector<ParameterBlock>& parameter_blocks() const { return parameter_blocks_; }
  const std::vector<ResidualBlock>& residual_blocks() const { return residual_blocks_; }
  const std::vector<double*>& parameters() const { return parameters_; }

 private:
  std::vector<ParameterBlock> parameter_blocks_;
  std::vector<ResidualBlock> residual_blocks_;
  std::vector<double*> parameters_;
};

// Solves `problem` in place. `eliminate`: the parameter blocks removed by the Schur complement
// (the 3D points; each residual block may hold at most one of them, and only blocks of size 3
// can be eliminated); every other variable block enters the dense reduced system, in the order
// of their addresses (the order Ceres gives a group of its elimination ordering).
DenseSchurSummary SolveWithDenseSchur(const DenseSchurOptions& options,
                                      const std::vector<double*>& eliminate,
                                      ceres::Problem* problem);
// The same on a SchurProblem (its parameters change in place).
DenseSchurSummary SolveWithDenseSchur(const DenseSchurOptions& options,
                                      const std::vector<double*>& eliminate,
                                      const SchurProblem& problem);

}  // namespace varsfm
