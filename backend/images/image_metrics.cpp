#include "backend/images/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace patchsim {

namespace {

void checkFinite(const Image& image, const char* which) {
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        if (std::isfinite(image.rgb[i])) continue;
        const std::size_t pixel = i / 3, w = std::size_t(std::max(image.width, 1));
        throw std::domain_error(std::string("image metrics: the ") + which +
                                " has a non-finite value at pixel (" + std::to_string(pixel % w) +
                                ", " + std::to_string(pixel / w) + ")");
    }
}

// Same size, and every value finite: a NaN would otherwise slip through the clamps and comparisons
// and read as a perfect score (an infinite PSNR).
void checkSizes(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("image metrics: images of different sizes");
    checkFinite(a, "image");
    checkFinite(b, "reference");
}

double meanSquaredError(const Image& a, const Image& b) {
    checkSizes(a, b);
    double sum = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        const double d =
            double(std::clamp(a.rgb[i], 0.0f, 1.0f)) - std::clamp(b.rgb[i], 0.0f, 1.0f);
        sum += d * d;
    }
    return a.rgb.empty() ? 0.0 : sum / double(a.rgb.size());
}

std::vector<double> displayLuma(const Image& image) {
    std::vector<double> luma(std::size_t(image.width) * std::size_t(image.height));
    for (std::size_t p = 0; p < luma.size(); ++p)
        luma[p] = 0.299 * linearToSrgb(image.rgb[3 * p]) +
                  0.587 * linearToSrgb(image.rgb[3 * p + 1]) +
                  0.114 * linearToSrgb(image.rgb[3 * p + 2]);
    return luma;
}

}  // namespace

double rmse(const Image& image, const Image& reference) {
    return std::sqrt(meanSquaredError(image, reference));
}

double psnr(const Image& image, const Image& reference) {
    const double mse = meanSquaredError(image, reference);
    return mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

double ssim(const Image& image, const Image& reference) {
    checkSizes(image, reference);
    constexpr double kC1 = (0.01 * 1.0) * (0.01 * 1.0), kC2 = (0.03 * 1.0) * (0.03 * 1.0);
    const int w = image.width, h = image.height;
    const int size = std::min({11, w, h}), radius = size / 2;
    std::vector<double> window(std::size_t(size) * std::size_t(size));
    double total = 0;
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const double dx = i - (size - 1) / 2.0, dy = j - (size - 1) / 2.0;
            total += window[std::size_t(j * size + i)] =
                std::exp(-(dx * dx + dy * dy) / (2 * 1.5 * 1.5));
        }
    for (double& g : window) g /= total;
    const std::vector<double> x = displayLuma(image), y = displayLuma(reference);
    double sum = 0;
    int windows = 0;
    for (int cy = radius; cy + (size - 1 - radius) < h; ++cy) {
        for (int cx = radius; cx + (size - 1 - radius) < w; ++cx) {
            double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
            for (int j = 0; j < size; ++j)
                for (int i = 0; i < size; ++i) {
                    const std::size_t p = std::size_t(cy - radius + j) * std::size_t(w) +
                                          std::size_t(cx - radius + i);
                    const double g = window[std::size_t(j * size + i)];
                    mx += g * x[p];
                    my += g * y[p];
                    xx += g * x[p] * x[p];
                    yy += g * y[p] * y[p];
                    xy += g * x[p] * y[p];
                }
            const double vx = xx - mx * mx, vy = yy - my * my, cov = xy - mx * my;
            sum += ((2 * mx * my + kC1) * (2 * cov + kC2)) /
                   ((mx * mx + my * my + kC1) * (vx + vy + kC2));
            ++windows;
        }
    }
    return windows ? sum / windows : 1.0;
}

double meanAbsoluteDifference(std::span<const float> a, std::span<const float> b) {
    if (a.size() != b.size()) throw std::invalid_argument("image metrics: AOVs of different sizes");
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(a[i]) || !std::isfinite(b[i]))
            throw std::domain_error("image metrics: an AOV has a non-finite value at " +
                                    std::to_string(i));
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(double(a[i]) - b[i]);
    return a.empty() ? 0.0 : sum / double(a.size());
}

}  // namespace patchsim
