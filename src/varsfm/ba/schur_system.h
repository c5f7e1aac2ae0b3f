#pragma once
// The normal equations of a least-squares problem with the points eliminated by the Schur
// complement (Triggs et al., "Bundle adjustment - a modern synthesis", 2000, sec. 6.1), the
// linear algebra of the Schur solver (schur_solver.h); the trust region (trust_region.h) decides
// which damping to solve with and which steps to keep. In order:
//  - schur_system.cc: the structure, built once: the variable blocks (the reduced system's
//    columns first, then the points), the couplings W between points and other blocks, the
//    parts the work is cut into (part_runner.h);
//  - schur_linearisation.cc: residuals, loss-corrected Jacobians in tangent coordinates, and the
//    blocks S, W, V and gradient g of J^T J and J^T r;
//  - schur_elimination.cc: the damped step, V^-1 and the Schur terms of every point, back-
//    substitution for the points' steps;
//  - reduced_camera_system.cc: the reduced system's block pattern, its Jacobi scaling and
//    Cholesky factorisation, dense or sparse (cholesky.h);
//  - schur_step.cc: moving the parameters along a step (on their manifolds) and back, and the
//    terms of Powell's dogleg.
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "varsfm/ba/cholesky.h"
#include "varsfm/ba/least_squares_problem.h"
#include "varsfm/ba/part_runner.h"
#include "varsfm/ba/schur_solver.h"

// The loops over residuals and points are compiled twice, for x86-64-v3 (AVX2, FMA) and for the
// baseline, and the loader picks the one the CPU runs (GCC's function multi-versioning): Debian's
// packages target the baseline, and the 9 x 9 block products run faster four doubles wide. FMA
// rounds differently: a result is the same bit for bit on one machine, not between CPUs with and
// without AVX2.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define VARSFM_CPU_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define VARSFM_CPU_CLONES
#endif

namespace varsfm {

class SchurSystem {
 public:
  // Fails (ok() false) when a residual uses a block that was not added to the problem.
  // The factorisation, threads and iterative solve's settings come from `options`.
  SchurSystem(const std::vector<double*>& eliminate, const SchurSolverOptions& options,
              const LeastSquaresProblem& problem);

  bool ok() const { return ok_; }

  int num_columns() const { return num_columns_; }
  double seconds_factorise() const { return seconds_factorise_; }
  // sum |r|^2 (no loss) at the parameters of the last Evaluate.
  double squared_norm() const { return squared_norm_; }
  bool sparse() const { return sparse_; }
  bool iterative() const { return iterative_; }
  int cg_iterations() const { return cg_iterations_; }
  double fill() const { return fill_; }

  // The cost 1/2 sum rho(|r|^2) at the current parameters, and with `linearise` the normal
  // equations' blocks (S, W, V, g) of the loss-corrected Jacobian. False when a cost function
  // fails.
  bool Evaluate(bool linearise, double* cost);

  // The max-norm of the gradient J^T r (tangent coordinates).
  double GradientMaxNorm() const;

  // Solves (J^T J + mu D) delta = -J^T r through the Schur complement of the points. Returns
  // false when the reduced system is not positive definite. `model_decrease` is the decrease of
  // the linearised cost, -1/2 g^T delta + 1/2 mu delta^T D delta (from the damped equations).
  bool SolveStep(double mu, double* model_decrease, double* step_norm);

  // Powell's dogleg (Nocedal & Wright, "Numerical Optimization", 2nd ed., sec. 4.1; Ceres'
  // DoglegStrategy) combines the Gauss-Newton step p (the last SolveStep, with its small mu)
  // and the Cauchy point along u = D^-1 g, the gradient in the Jacobi-scaled coordinates. The
  // model of every step a p + b u follows from five scalars: with (H + mu D) p = -g,
  // p^T H p = -g.p - mu p^T D p and u^T H p = -g.u - mu g.p; only u^T H u needs the blocks.
  struct DoglegTerms {
    double mu = 0.0;
    double g_p = 0.0;    // g . p
    double p_D_p = 0.0;  // p^T D p
    double g_u = 0.0;    // g . u = |u|_D^2
    double u_H_u = 0.0;
    // After an inexact (iterative) solve, rho = (H + mu D) p + g is not zero: p^T H p and
    // u^T H p gain p . rho and u . rho (zero after a Cholesky solve).
    double p_rho = 0.0;
    double u_rho = 0.0;
  };

  // Keeps the last step as the Gauss-Newton step p (solved with damping mu) and computes u.
  DoglegTerms KeepGaussNewtonStep(double mu);

  // The step a p + b u into delta (for Step()); returns its Euclidean norm.
  double SetDoglegStep(double a, double b);

  // x <- x [+] delta, keeping the previous values for Restore(). False when a manifold fails.
  bool Step();
  void Restore();
  double ParameterNorm() const;

 private:
  static constexpr int kParts = kSchurParts;

  // Ceres' bounds on the Levenberg-Marquardt diagonal D (solver.h).
  static double ClampDiagonal(double d) { return std::clamp(d, 1e-6, 1e32); }

  // A non-zero of a manifold's plus-Jacobian: a product of subsets and rotations is mostly zeros
  // (the 14 x 9 Jacobian of an image block has 18 non-zeros). A block keeps them column by
  // column, each column's by row.
  struct PlusEntry {
    int row = 0;
    int col = 0;
    double value = 0.0;
  };

  // A variable parameter block: either a column range of the reduced system or an eliminated
  // point.
  struct Block {
    double* x = nullptr;
    int size = 0;
    int tangent = 0;
    const ceres::Manifold* manifold = nullptr;  // null: Euclidean
    int column = -1;                            // first column in the reduced system
    int point = -1;                             // index of the eliminated point
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>
        plus_jacobian;                    // size x tangent at x (manifold blocks only)
    std::vector<PlusEntry> plus_entries;  // its non-zeros
  };

  // One (non-eliminated block, point) pair of the Schur complement: W = sum J_b^T J_p over the
  // residuals of the point that involve the block, stored column-major tangent_b x 3 at
  // `offset`.
  struct Coupling {
    int block = 0;
    size_t offset = 0;
  };

  // A residual block; its parameter blocks are entries [begin, begin + count) of the flat arrays
  // (one allocation for all residuals: the per-residual walk is memory-bound).
  struct Residual {
    const ceres::CostFunction* cost = nullptr;
    const ceres::LossFunction* loss = nullptr;
    int begin = 0;
    int count = 0;
    int point_parameter = -1;  // which parameter block is the eliminated point, if any
    int point = -1;            // that point's index
  };

  // A block (a, b) of the reduced system that residuals write directly (two non-eliminated
  // blocks of one residual: an image's diagonal block, an image with a shared camera block): at
  // `offset` in the blocks, at `compact` in each part's buffer.
  struct ResidualPair {
    size_t offset = 0;
    size_t compact = 0;
    size_t size = 0;
  };

  // One part's buffers for Evaluate: its residuals' scratch and its share of the sums that
  // several parts write (the reduced system's columns' gradient, the blocks that residuals
  // couple directly, the cost).
  struct PartScratch {
    std::vector<double> r;
    std::vector<std::vector<double>> raw, tangent;
    std::vector<double*> jacobians;
    std::vector<double> s;  // residual-coupled blocks, at their compact offsets
    Eigen::VectorXd g;
    double cost = 0.0;
    double squared_norm = 0.0;  // sum |r|^2, without the loss
  };

  bool AllPartsOk() const {
    return std::find(part_ok_.begin(), part_ok_.end(), false) == part_ok_.end();
  }

  // The index of block (a, b), a <= b, in pair_block_ / pair_offset_.
  int PairIndex(int a, int b) const {
    const auto first = pair_block_.begin() + pair_begin_[a];
    const auto last = pair_block_.begin() + pair_begin_[a + 1];
    return static_cast<int>(std::lower_bound(first, last, b) - pair_block_.begin());
  }

  // Structure (schur_system.cc).
  bool BuildBlocks(const std::vector<double*>& eliminate, const LeastSquaresProblem& problem);
  void BuildCouplings();
  void PartitionResiduals();
  void BuildResidualPairs();
  void BuildRowGroups();

  // Linearisation (schur_linearisation.cc).
  VARSFM_CPU_CLONES bool EvaluatePart(int k, bool linearise);
  void ZeroPoint(int p);
  static bool UpdatePlusJacobian(Block* b);

  // Elimination (schur_elimination.cc).
  VARSFM_CPU_CLONES bool InvertPoints(int k, double mu);
  VARSFM_CPU_CLONES void EliminatePoints(int k, double mu);
  VARSFM_CPU_CLONES bool BackSubstitute(int k);

  // The reduced camera system (reduced_camera_system.cc).
  void BuildReducedStructure();
  void BuildSparsePattern();
  bool SolveReducedSystem();
  void FillSparse(const Eigen::VectorXd& scale);
  void FillDense(const Eigen::VectorXd& scale, Eigen::MatrixXd* s) const;
  // Conjugate gradients (reduced_camera_pcg.cc).
  void MultiplyScaledReduced(const Eigen::VectorXd& scale, const Eigen::VectorXd& x,
                             Eigen::VectorXd* y) const;
  bool SolveScaledReducedIteratively(const Eigen::VectorXd& scale, const Eigen::VectorXd& b,
                                     Eigen::VectorXd* y);

  std::vector<Block> blocks_;
  std::vector<Residual> residuals_;
  std::vector<double*> values_;   // per residual parameter: the cost function's block
  std::vector<int> block_of_;     // its index in blocks_, -1 when constant
  std::vector<int> coupling_of_;  // its coupling with the residual's point, -1 when none
  std::vector<Coupling> couplings_;
  std::vector<int> point_couplings_begin_;
  int num_columns_ = 0;
  int num_points_ = 0;
  int num_parameters_ = 0;
  int max_residuals_ = 0;
  int max_parameters_ = 0;
  int max_block_size_ = 0;
  bool ok_ = false;  // every block the residuals use was declared
  // Normal equations at the current parameters (undamped).
  // The reduced system's blocks (a, b), a <= b: row a's are pair_block_[pair_begin_[a] ..
  // pair_begin_[a + 1]), each column-major tangent_a x tangent_b at pair_offset_.
  int num_column_blocks_ = 0;
  std::vector<int> pair_begin_;
  std::vector<int> pair_block_;
  std::vector<size_t> pair_offset_;
  std::vector<double> s_blocks_;  // J^T J (undamped)
  std::vector<double> work_;      // damped, minus the points' Schur terms
  SchurSolverOptions::Factorization factorization_;
  bool sparse_ = false;
  double fill_ = 0.0;
  int iterative_min_blocks_ = 0;
  double iterative_tolerance_ = 0.0;
  int iterative_max_iterations_ = 0;
  bool iterative_ = false;
  int cg_iterations_ = 0;
  Eigen::VectorXd reduced_residual_;      // S delta_c - rhs after an iterative solve
  Eigen::SparseMatrix<double> sparse_s_;  // upper triangle, pattern fixed at setup
  std::vector<int> pair_value_begin_;     // per block: its columns' entries in value_starts_
  std::vector<int> value_starts_;         // per block column: first index in sparse_s_'s values
  SparseCholesky sparse_llt_;
  Eigen::VectorXd g_c_;
  std::vector<double> w_;
  std::vector<Eigen::Matrix3d> v_;
  std::vector<Eigen::Vector3d> g_p_;
  // The last step.
  std::vector<Eigen::Matrix3d> v_inverse_;
  Eigen::VectorXd delta_c_;
  std::vector<Eigen::Vector3d> delta_p_;
  std::vector<double> point_g_delta_;  // g_p . delta_p
  std::vector<double> point_dDd_;      // delta_p^T D_p delta_p
  double step_g_delta_ = 0.0;          // g . delta of the last step
  double step_dDd_ = 0.0;              // delta^T D delta of the last step
  std::vector<double> backup_;
  // The dogleg's Gauss-Newton step and scaled gradient (KeepGaussNewtonStep).
  Eigen::VectorXd gn_c_, u_c_;
  std::vector<Eigen::Vector3d> gn_p_, u_p_;
  // The parts (kParts): residuals_[residual_part_begin_[k] .. [k + 1]) are points
  // [point_part_begin_[k] .. [k + 1]); rows [row_group_begin_[k] .. [k + 1]) of the reduced
  // system, updated by group_points_[k].
  PartRunner runner_;
  std::vector<int> residual_part_begin_;
  std::vector<int> point_part_begin_;
  std::vector<int> row_group_begin_;
  std::vector<std::vector<int>> group_points_;
  std::array<PartScratch, kParts> parts_;
  std::array<bool, kParts> part_ok_{};
  std::vector<ResidualPair> residual_pairs_;
  std::vector<size_t> compact_of_pair_;  // per block pair: its compact offset (residual pairs)
  Eigen::VectorXd rhs_;                  // the reduced system's right-hand side
  double seconds_factorise_ = 0.0;       // SolveStep's factorisations, summed
  double squared_norm_ = 0.0;
};

}  // namespace varsfm
