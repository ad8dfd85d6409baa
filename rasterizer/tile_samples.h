#pragma once
// The samples of every screen tile, made once per frame and ordered by time (issue: samples per
// tile precomputed, so a tile's time range is an index range).
//
// Representation
// --------------
// One array of TileSample, tile after tile (row-major tiles of the rasterizer's grid); within a
// tile, samples in order of time (ties by their visibility-buffer index, so the order is fixed).
// A TileSample holds what a ray needs without going back to the sample set: its time, its point
// on the z = -1 plane, its lens point on the unit disk (and the lens sample in [0,1)^2 the
// visibility record keeps), and its index in the visibility buffer. A tile's samples in a time
// range [tmin, tmax] are one contiguous span, found by binary search: samples outside it cost
// nothing. 32 bytes a sample, the size of its visibility record.

#include <cstdint>
#include <span>
#include <vector>

#include "pipeline/core/camera.h"
#include "pipeline/core/ray.h"
#include "pipeline/core/samples.h"
#include "pipeline/core/time_range.h"
#include "rasterizer/tile_grid.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

struct TileSample {
    float time;
    Vec2 screen;           // on the z = -1 plane
    Vec2 disk;             // lens point on the unit disk
    Vec2 lens;             // lens sample in [0,1)^2
    std::uint32_t record;  // index in the visibility buffer
};
static_assert(sizeof(TileSample) == 32);

class TileSamples {
  public:
    TileSamples(const TileGrid& grid, const Camera& camera, const SampleGenerator& samples,
                int threads);

    std::span<const TileSample> tile(int tx, int ty) const;
    // The tile's samples with time in `times`.
    std::span<const TileSample> inTime(int tx, int ty, TimeRange times) const;

    // The sample's ray, with the camera's near-to-far range.
    static Ray ray(const TileSample& s, const Camera& camera, const LensModel& lens) {
        return makeCameraRay(camera, s.screen, s.disk, s.time, lens);
    }

  private:
    TileGrid grid_;
    std::vector<TileSample> samples_;
    std::vector<std::uint32_t> begin_;  // per tile, tileCount + 1
};

}  // namespace patchsim
