#pragma once
// Error of an image against a converged one (DESIGN.md section 9).
//
// - RMSE and PSNR on linear RGB clamped to [0, 1], over every pixel and channel; PSNR uses a peak
//   of 1: 10 log10(1 / MSE), infinite for identical images.
// - SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on the luma of the displayed image (sRGB-encoded,
//   Y' = 0.299 R' + 0.587 G' + 0.114 B', in [0, 1]), with their constants: an 11 x 11 Gaussian
//   window of sigma 1.5, K1 = 0.01, K2 = 0.03, dynamic range L = 1; the mean of the SSIM map over
//   the windows that lie wholly inside the image (their "valid" region). Images smaller than the
//   window are compared as one window.
// - Coverage error: the mean absolute difference of the coverage AOV (fraction of a pixel's
//   samples that hit something).
// Every metric throws std::domain_error when either image holds a NaN or an infinity: an error
// metric of a broken image is an error, never a number (a NaN would read as an infinite PSNR).

#include <span>
#include <vector>

#include "backend/images/image.h"

namespace patchsim {

struct ImageError {
    double rmse = 0, psnr = 0, ssim = 1, coverage = 0;
};

double rmse(const Image& image, const Image& reference);
double psnr(const Image& image, const Image& reference);
double ssim(const Image& image, const Image& reference);
double meanAbsoluteDifference(std::span<const float> a, std::span<const float> b);

}  // namespace patchsim
