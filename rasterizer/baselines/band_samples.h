#pragma once
// The samples of a band of rows as rays, made once before the band's triangles and tested a SIMD
// vector at a time (the bounding baselines' counterpart of the patch method's TileRays).
//
// Representation
// --------------
// Structure of arrays in the visibility buffer's order within the band, (row - y0, x, s): each
// per-sample quantity is one array, so consecutive samples of a pixel, and of the pixels of a
// row, load as one vector. Per sample: the ray's origin, the shear of the watertight triangle
// test (axes kx, ky, kz and sx, sy, sz), its time, where the near plane lies along it and its
// depth per unit of ray parameter; the sample's screen position on the z = -1 plane (for the hull
// test) and lens sample (for the record). For the interval method each pixel's samples are also
// listed in order of time stratum, so a stratum's samples are a range found by binary search, not
// a scan of the pixel's samples once per stratum.
//
// A triangle's candidates (the samples its bound reaches) are gathered row by row into a list of
// sample indices with their ray ends (CandidateList), and the list is tested against the triangle
// in one call (testCandidates). Rays that shear along z with kx = 1, ky = 0 (every camera ray that
// looks down -z more than sideways) go in the list; the others take the scalar test. The vector
// test performs the scalar test's float operations in the same order (watertight_triangle.h),
// so every hit, and every image, is the same bit for bit on every SIMD target.
//
// Why the samples are made once: the generator's hashing and permutations, the lens mapping and
// the ray's shear cost more than the ray-triangle test they feed, and a sample is tested against
// every triangle whose bound holds it.

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/math.h"
#include "core/samples.h"
#include "rasterizer/common/sample_rays.h"
#include "rasterizer/common/screen_triangle.h"
#include "rasterizer/common/watertight_triangle.h"

namespace patchsim {

// The widest vector the sample test uses (16 floats: AVX-512); narrower targets split a list.
inline constexpr int kSampleLanes = 16;

class BandSamples {
  public:
    // Samples of rows [y0, y1); with `strata` > 0 each pixel's samples are also ordered by time
    // stratum (of `strata` equal parts of the shutter).
    BandSamples(const RayCaster& caster, int width, int spp, int y0, int y1, int strata);

    // The bytes held per sample, with or without the stratum order, with or without the two
    // floats a static frame's sub-pixel positions or a defocus-only frame's lens points take
    // (Effects::screenPlaneSamples, Effects::lensPlaneSamples).
    static std::uint64_t bytesPerSample(bool strata, bool planeSamples);

    std::size_t index(int row, int x, int s) const {
        return (std::size_t(row) * std::size_t(width_) + std::size_t(x)) * std::size_t(spp_) +
               std::size_t(s);
    }
    // The first and one-past-last positions of pixel (row, x)'s samples of `stratum` in its
    // stratum order (stratumSample).
    void stratumRange(int row, int x, int stratum, std::size_t& first, std::size_t& last) const;
    int stratumSample(std::size_t position) const { return byStratum_[position]; }

    // The vector test can take this sample (it shears along z with kx = 1, ky = 0).
    bool alongZ(std::size_t i) const { return axes_[i] == kAlongZ; }
    ShearedRay shearedRay(std::size_t i) const;
    Vec2 screen(std::size_t i) const { return {screenX_[i], screenY_[i]}; }
    // In a static frame: the raster position on the sub-pixel grid (screen_triangle.h).
    bool hasSubpixels() const { return !subpixelX_.empty(); }
    double subpixelX(std::size_t i) const { return subpixelX_[i]; }
    double subpixelY(std::size_t i) const { return subpixelY_[i]; }
    // In a defocus-only frame: the ray's origin on the lens (radius times the disk sample), the
    // lens edge test's lens point (lens_triangle.h).
    bool hasLensPoints() const { return !lensPointX_.empty(); }
    Vec2 lensPoint(std::size_t i) const { return {lensPointX_[i], lensPointY_[i]}; }
    Vec2 lens(std::size_t i) const { return {lensU_[i], lensV_[i]}; }
    float time(std::size_t i) const { return time_[i]; }
    float lambdaMin(std::size_t i) const { return lambdaMin_[i]; }
    float depthPerLambda(std::size_t i) const { return depthPerLambda_[i]; }

    // The arrays the vector test reads, of `count` samples.
    struct Lanes {
        const float *originX, *originY, *originZ, *shearX, *shearY, *shearZ, *time, *lambdaMin;
        std::int64_t count;
    };
    Lanes lanes() const {
        return {originX_.data(), originY_.data(),   originZ_.data(),
                shearX_.data(),  shearY_.data(),    shearZ_.data(),
                time_.data(),    lambdaMin_.data(), std::int64_t(time_.size())};
    }

  private:
    // kx | ky << 2 | kz << 4
    static constexpr std::uint8_t kAlongZ = 1 | 0 << 2 | 2 << 4;
    static constexpr std::size_t kFloatArrays = 13;  // the float arrays below
    void orderByStratum(int strata);

    int width_, spp_;
    std::vector<float> originX_, originY_, originZ_, shearX_, shearY_, shearZ_, time_, lambdaMin_;
    std::vector<float> depthPerLambda_, screenX_, screenY_, lensU_, lensV_;
    std::vector<std::uint8_t> axes_;
    std::vector<float> subpixelX_, subpixelY_;  // integers below 2^24, exact in float
    std::vector<float> lensPointX_, lensPointY_;
    std::vector<std::uint16_t> byStratum_;  // per pixel, spp sample indices in order of stratum
    std::vector<std::uint16_t> stratum_;    // the stratum of each of those
};

// A triangle moving linearly over the shutter: its corners at shutter open and close.
struct MovingTriangle {
    Vec3 open[3], close[3];
};

// A hit of the vector test: the candidate's position in its list, the ray parameter and the
// barycentrics of vertices 1 and 2.
struct CandidateHit {
    std::int32_t candidate;
    float lambda, b1, b2;
};

// Samples to test against one triangle: their indices in the band and their rays' ends. Made
// with room for `capacity` candidates; nothing is allocated while it is filled and tested.
class CandidateList {
  public:
    explicit CandidateList(std::size_t capacity);
    static std::uint64_t bytesFor(std::uint64_t capacity) {
        return (capacity + kSampleLanes) * (sizeof(std::int32_t) + sizeof(float)) +
               capacity * sizeof(CandidateHit);
    }
    void clear() { count_ = 0; }
    void add(std::int32_t sample, float lambdaMax) {
        index_[count_] = sample;
        lambdaMax_[count_++] = lambdaMax;
    }
    int size() const { return int(count_); }
    std::int32_t sample(int candidate) const { return index_[std::size_t(candidate)]; }

    // Every candidate against `triangle`; hits go to `hits()` in candidate order. Returns their
    // number.
    int test(const BandSamples& samples, const MovingTriangle& triangle);
    const CandidateHit* hits() const { return hits_.data(); }

  private:
    std::size_t count_ = 0;
    // Padded by a vector: the tail of the last vector reads valid (masked-off) entries.
    std::vector<std::int32_t> index_;
    std::vector<float> lambdaMax_;
    std::vector<CandidateHit> hits_;
};

}  // namespace patchsim
