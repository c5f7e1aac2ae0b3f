#pragma once
// Internal to the matching module: brute-force nearest-neighbour search between two sets of
// uint8 SIFT descriptors by cosine similarity. For every descriptor of each set it finds the
// best and second-best score in the other set (two-sided, so the ratio test can be applied in
// both directions as COLMAP does).
//
// Scores are cos(angle) = <a, b> / (|a| |b|). The dot products of uint8 vectors of length 128
// are integers below 2^24, so both kernels compute them exactly (int32 with AVX-512 VNNI, or
// float32 GEMM whose partial sums stay exact integers) and then scale them by the same float
// operations in the same order: the kernels give bit-identical results.
#include <cstdint>
#include <vector>

#include "varsfm/feature/types.h"

namespace varsfm::internal {

enum class NnKernel {
  kGeneric,    // Eigen float GEMM, any CPU
  kAvx512Vnni  // int8 dot products (vpdpbusd), chosen at run time where the CPU has it
};

// True when this CPU can run the AVX-512 VNNI kernel.
bool CpuHasAvx512Vnni();

// One image's descriptors laid out for a kernel; built once per image and reused by every pair.
struct PreparedDescriptors {
  NnKernel kernel = NnKernel::kGeneric;
  int num = 0;                  // number of descriptors
  std::vector<float> inv_norm;  // 1/|d| (0 for an all-zero descriptor), padded with zeros
  // kGeneric: num x 128 float copy of the raw values.
  Eigen::Matrix<float, Eigen::Dynamic, 128, Eigen::RowMajor> as_float;
  // kAvx512Vnni: rows as uint8 (padded to a multiple of 8 rows) for the "A" role, their byte
  // sums (for the signed-offset correction), and the "B" role packed per 32-column tile as
  // (value - 128) int8 in groups of 4 bytes, the layout vpdpbusd consumes.
  std::vector<uint8_t> rows;
  std::vector<int32_t> row_sum;
  std::vector<int8_t> packed;
};

PreparedDescriptors PrepareDescriptors(const FeatureDescriptors& descriptors, NnKernel kernel);

// Best / second-best scores of each row of A over B ("row") and of each row of B over A ("col").
// Ties go to the smallest index; a tie for the best makes second == best.
struct NearestNeighbors {
  std::vector<int> row_best;
  std::vector<float> row_best_score, row_second_score;
  std::vector<int> col_best;
  std::vector<float> col_best_score, col_second_score;
};

void FindNearestNeighborsGeneric(const PreparedDescriptors& a, const PreparedDescriptors& b,
                                 NearestNeighbors* nn);
void FindNearestNeighborsAvx512Vnni(const PreparedDescriptors& a, const PreparedDescriptors& b,
                                    NearestNeighbors* nn);

}  // namespace varsfm::internal
