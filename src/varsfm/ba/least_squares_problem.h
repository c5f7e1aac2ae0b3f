#pragma once
// A robust non-linear least-squares problem as the Schur solver (schur_solver.h) sees it:
// parameter blocks (on a manifold, or held whole) and residual blocks over them, nothing owned.
// The blocks are those of a ceres::Problem (cost functions, loss functions and manifolds through
// their public interfaces), so a model is defined once and either solver runs it. The mapper
// builds one directly instead of a ceres::Problem, which keeps a hash map per block and checks
// and a heap object per residual (docs/mapper.md, "Speed"). Every block a residual uses must be
// added once, before or after its residuals.
#include <cstddef>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

namespace varsfm {

class LeastSquaresProblem {
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

  // The blocks of `problem` as it is built (its parameters change in place when solved).
  static LeastSquaresProblem ViewOf(ceres::Problem* problem);

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

}  // namespace varsfm
