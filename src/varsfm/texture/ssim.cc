#include "varsfm/texture/ssim.h"

#include <vector>

#include <opencv2/imgproc.hpp>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

constexpr int kWindow = 11;
constexpr double kSigma = 1.5;

cv::Mat Blur(const cv::Mat& image) {
  cv::Mat out;
  cv::GaussianBlur(image, out, cv::Size(kWindow, kWindow), kSigma, kSigma, cv::BORDER_REFLECT);
  return out;
}

}  // namespace

double MaskedSsim(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  if (a.size() != b.size() || a.type() != b.type() || mask.size() != a.size() ||
      a.depth() != CV_8U || mask.type() != CV_8UC1) {
    Fail("SSIM: images of {}x{} and {}x{} (or their mask) do not match", a.cols, a.rows, b.cols,
         b.rows);
  }
  cv::Mat scored;
  cv::erode(mask, scored, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kWindow, kWindow)));
  if (cv::countNonZero(scored) == 0) scored = mask;
  if (cv::countNonZero(scored) == 0) return 0;

  constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
  constexpr double kC2 = (0.03 * 255) * (0.03 * 255);
  std::vector<cv::Mat> channels_a, channels_b;
  cv::split(a, channels_a);
  cv::split(b, channels_b);
  double sum = 0;
  for (size_t c = 0; c < channels_a.size(); ++c) {
    // One channel at a time: OpenCV adds a scalar to the first channel only of a multi-channel
    // matrix.
    cv::Mat x, y;
    channels_a[c].convertTo(x, CV_64F);
    channels_b[c].convertTo(y, CV_64F);
    const cv::Mat mu_x = Blur(x), mu_y = Blur(y);
    const cv::Mat mu_xx = mu_x.mul(mu_x), mu_yy = mu_y.mul(mu_y), mu_xy = mu_x.mul(mu_y);
    const cv::Mat var_x = Blur(x.mul(x)) - mu_xx;
    const cv::Mat var_y = Blur(y.mul(y)) - mu_yy;
    const cv::Mat cov = Blur(x.mul(y)) - mu_xy;
    const cv::Mat numerator = (2 * mu_xy + kC1).mul(2 * cov + kC2);
    const cv::Mat denominator = (mu_xx + mu_yy + kC1).mul(var_x + var_y + kC2);
    cv::Mat ssim;
    cv::divide(numerator, denominator, ssim);
    sum += cv::mean(ssim, scored)[0];
  }
  return sum / static_cast<double>(channels_a.size());
}

}  // namespace varsfm
