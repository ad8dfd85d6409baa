#include "backend/images/image_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace patchsim {
namespace {

Image filled(int w, int h, float v) {
    Image image(w, h);
    for (float& c : image.rgb) c = v;
    return image;
}

Image noise(int w, int h, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.2f, 0.8f);
    Image image(w, h);
    for (float& c : image.rgb) c = u(rng);
    return image;
}

TEST(ImageMetrics, IdenticalImagesHaveNoError) {
    const Image a = noise(40, 30, 1);
    EXPECT_EQ(rmse(a, a), 0.0);
    EXPECT_TRUE(std::isinf(psnr(a, a)));
    EXPECT_DOUBLE_EQ(ssim(a, a), 1.0);
}

// A constant difference d gives MSE d^2: PSNR 20 dB at d = 0.1, 40 dB at 0.01.
TEST(ImageMetrics, PsnrOfAKnownDifference) {
    EXPECT_NEAR(psnr(filled(16, 16, 0.5f), filled(16, 16, 0.6f)), 20.0, 1e-5);
    EXPECT_NEAR(psnr(filled(16, 16, 0.5f), filled(16, 16, 0.51f)), 40.0, 1e-3);
    EXPECT_NEAR(rmse(filled(16, 16, 0.5f), filled(16, 16, 0.6f)), 0.1, 1e-6);
    // Values are clamped to [0, 1] first: out-of-range light does not count.
    EXPECT_EQ(rmse(filled(8, 8, 1.0f), filled(8, 8, 3.0f)), 0.0);
}

// Flat images: no variance, so SSIM is its luminance term (2ab + C1) / (a^2 + b^2 + C1) exactly,
// with a and b the displayed (sRGB) values.
TEST(ImageMetrics, SsimOfFlatImagesIsTheLuminanceTerm) {
    for (auto [u, v] : {std::pair{0.2f, 0.4f}, std::pair{0.5f, 0.05f}, std::pair{0.9f, 0.8f}}) {
        const double a = linearToSrgb(u), b = linearToSrgb(v), c1 = 1e-4;
        const double expected = (2 * a * b + c1) / (a * a + b * b + c1);
        EXPECT_NEAR(ssim(filled(20, 20, u), filled(20, 20, v)), expected, 1e-9) << u << " " << v;
    }
}

// Known values from an independent implementation: scikit-image 0.19.3 (Debian 12's
// python3-skimage), structural_similarity(X, Y, gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=1) on the sRGB-encoded grey images below.
TEST(ImageMetrics, SsimMatchesScikitImageOnKnownPairs) {
    const int w = 32, h = 24;
    Image x(w, h), y(w, h), inverted(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const float v = 0.5f + 0.3f * std::sin(0.7f * float(i)) * std::cos(0.45f * float(j));
            const float shifted =
                std::clamp(v + 0.1f * std::sin(1.3f * float(i) + 0.2f * float(j)), 0.0f, 1.0f);
            x.set(i, j, Vec3(v));
            y.set(i, j, Vec3(shifted));
            inverted.set(i, j, Vec3(1.0f - v));
        }
    EXPECT_NEAR(ssim(x, y), 0.8760518934548667, 2e-5);
    EXPECT_NEAR(ssim(x, inverted), -0.8613838307584747, 2e-5);
    EXPECT_NEAR(ssim(y, x), ssim(x, y), 1e-12);  // symmetric
}

TEST(ImageMetrics, SsimFallsWithNoise) {
    const Image base = noise(32, 24, 2);
    EXPECT_LT(ssim(noise(32, 24, 3), base), 0.5);
}

TEST(ImageMetrics, CoverageErrorIsTheMeanAbsoluteDifference) {
    const std::vector<float> a{0, 0.5f, 1, 1}, b{0, 1, 0.75f, 1};
    EXPECT_DOUBLE_EQ(meanAbsoluteDifference(a, b), 0.1875);
}

// A NaN slips through clamps and comparisons (its PSNR read as infinite, "perfect"): every metric
// refuses a non-finite image instead of returning a number.
TEST(ImageMetrics, NonFiniteImagesAreAnErrorNotAScore) {
    const Image base = noise(16, 12, 2);
    for (float bad :
         {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
          std::numeric_limits<float>::infinity()}) {
        Image broken = base;
        broken.rgb[3 * (5 * 16 + 7) + 1] = bad;
        EXPECT_THROW(rmse(broken, base), std::domain_error);
        EXPECT_THROW(psnr(broken, base), std::domain_error);
        EXPECT_THROW(psnr(base, broken), std::domain_error);
        EXPECT_THROW(ssim(broken, base), std::domain_error);
        try {
            psnr(broken, base);
        } catch (const std::domain_error& e) {
            EXPECT_NE(std::string(e.what()).find("non-finite value at pixel (7, 5)"),
                      std::string::npos)
                << e.what();
        }
        const std::vector<float> coverage{0, bad}, fine{0, 1};
        EXPECT_THROW(meanAbsoluteDifference(coverage, fine), std::domain_error);
    }
    EXPECT_TRUE(std::isinf(psnr(base, base)));  // identical images: infinite, as defined
}

}  // namespace
}  // namespace patchsim
