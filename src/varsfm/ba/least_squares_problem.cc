#include "varsfm/ba/least_squares_problem.h"

namespace varsfm {

LeastSquaresProblem LeastSquaresProblem::ViewOf(ceres::Problem* problem) {
  LeastSquaresProblem view;
  std::vector<double*> blocks;
  problem->GetParameterBlocks(&blocks);
  for (double* x : blocks)
    view.AddParameterBlock(x, problem->ParameterBlockSize(x), problem->GetManifold(x),
                           problem->IsParameterBlockConstant(x));
  std::vector<ceres::ResidualBlockId> ids;
  problem->GetResidualBlocks(&ids);
  for (const ceres::ResidualBlockId id : ids) {
    problem->GetParameterBlocksForResidualBlock(id, &blocks);
    view.AddResidualBlock(problem->GetCostFunctionForResidualBlock(id),
                          problem->GetLossFunctionForResidualBlock(id), blocks.data(),
                          static_cast<int>(blocks.size()));
  }
  return view;
}

void LeastSquaresProblem::Reserve(size_t num_parameter_blocks, size_t num_residual_blocks,
                                  size_t num_parameters) {
  parameter_blocks_.reserve(num_parameter_blocks);
  residual_blocks_.reserve(num_residual_blocks);
  parameters_.reserve(num_parameters);
}

void LeastSquaresProblem::AddParameterBlock(double* x, int size, const ceres::Manifold* manifold,
                                            bool constant) {
  parameter_blocks_.push_back({x, size, manifold, constant});
}

void LeastSquaresProblem::AddResidualBlock(const ceres::CostFunction* cost,
                                           const ceres::LossFunction* loss,
                                           const double* const* blocks, int count) {
  residual_blocks_.push_back({cost, loss, static_cast<int>(parameters_.size()), count});
  // The solver writes through the blocks of its own parameters (the problem owns nothing).
  for (int i = 0; i < count; ++i) parameters_.push_back(const_cast<double*>(blocks[i]));
}

}  // namespace varsfm
