#include "varsfm/matching/nearest_neighbors.h"

#include <algorithm>
#include <cmath>

#include "varsfm/util/error.h"

namespace varsfm::internal {
namespace {

constexpr int kDim = 128;
constexpr float kNoScore = -1.0f;  // below any cosine of non-negative vectors

void Reset(int n1, int n2, NearestNeighbors* nn) {
  nn->row_best.assign(n1, -1);
  nn->row_best_score.assign(n1, kNoScore);
  nn->row_second_score.assign(n1, kNoScore);
  nn->col_best.assign(n2, -1);
  nn->col_best_score.assign(n2, kNoScore);
  nn->col_second_score.assign(n2, kNoScore);
}

}  // namespace

bool CpuHasAvx512Vnni() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vnni");
#else
  return false;
#endif
}

PreparedDescriptors PrepareDescriptors(const FeatureDescriptors& descriptors, NnKernel kernel) {
  if (descriptors.rows() > 0 && descriptors.cols() != kDim) {
    Fail("descriptor matching expects {}-byte SIFT descriptors, got {} columns", kDim,
         descriptors.cols());
  }
  PreparedDescriptors p;
  p.kernel = kernel;
  p.num = static_cast<int>(descriptors.rows());
  // Padding to whole 32-column tiles keeps the SIMD loads in bounds; padded entries are masked.
  const int padded32 = (p.num + 31) / 32 * 32;
  p.inv_norm.assign(padded32, 0.0f);
  for (int i = 0; i < p.num; ++i) {
    const float norm = descriptors.row(i).cast<float>().norm();
    p.inv_norm[i] = norm > 0 ? 1.0f / norm : 0.0f;
  }
  if (kernel == NnKernel::kGeneric) {
    p.as_float = descriptors.cast<float>();
    return p;
  }
  const int padded8 = (p.num + 7) / 8 * 8;
  p.rows.assign(static_cast<size_t>(padded8) * kDim, 0);
  p.row_sum.assign(padded8, 0);
  p.packed.assign(static_cast<size_t>(padded32) * kDim, static_cast<int8_t>(-128));
  for (int i = 0; i < p.num; ++i) {
    const uint8_t* src = descriptors.row(i).data();
    std::copy(src, src + kDim, p.rows.begin() + static_cast<size_t>(i) * kDim);
    int32_t sum = 0;
    for (int k = 0; k < kDim; ++k) sum += src[k];
    p.row_sum[i] = sum;
    // Tile t = i / 32 holds, for each group g of 4 dimensions, the 32 columns' 4 bytes in a row.
    const int t = i / 32, c = i % 32;
    for (int g = 0; g < kDim / 4; ++g) {
      int8_t* dst = &p.packed[(static_cast<size_t>(t) * 32 + g) * 128 + c * 4];
      for (int k = 0; k < 4; ++k) dst[k] = static_cast<int8_t>(int(src[4 * g + k]) - 128);
    }
  }
  return p;
}

void FindNearestNeighborsGeneric(const PreparedDescriptors& a, const PreparedDescriptors& b,
                                 NearestNeighbors* nn) {
  Reset(a.num, b.num, nn);
  if (a.num == 0 || b.num == 0) return;
  // Row blocks keep the dot-product block (64 x n2 floats) cache-sized.
  constexpr int kBlock = 64;
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> dots;
  for (int i0 = 0; i0 < a.num; i0 += kBlock) {
    const int rows = std::min(kBlock, a.num - i0);
    dots.noalias() = a.as_float.middleRows(i0, rows) * b.as_float.transpose();
    for (int r = 0; r < rows; ++r) {
      const int i = i0 + r;
      float m1 = kNoScore, m2 = kNoScore;
      int best = -1;
      for (int j = 0; j < b.num; ++j) {
        const float s = dots(r, j) * b.inv_norm[j] * a.inv_norm[i];
        if (s > m1) {
          m2 = m1, m1 = s, best = j;
        } else if (s > m2) {
          m2 = s;
        }
        float& c1 = nn->col_best_score[j];
        if (s > c1) {
          nn->col_second_score[j] = c1, c1 = s, nn->col_best[j] = i;
        } else if (s > nn->col_second_score[j]) {
          nn->col_second_score[j] = s;
        }
      }
      nn->row_best[i] = best;
      nn->row_best_score[i] = m1;
      nn->row_second_score[i] = m2;
    }
  }
}

}  // namespace varsfm::internal
