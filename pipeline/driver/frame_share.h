#pragma once
// The rows of a frame one rank rasterized, packed for rank 0 (DESIGN.md section 13: one frame split
// across ranks by screen tiles).
//
// Representation
// --------------
// Plain bytes, written and read in the same order on machines of the same kind (a homogeneous
// cluster): the owned pixel rows, each as its index and its samples' visibility records, its
// samples' transparent fragments (a count and the fragments) and its per-pixel work; the owned
// tile rows' tile-test counts; the work the rank's visibility step did for every patch, as the
// timing model's operations; and the counts its visibility step added to its counters. Rank 0
// copies the rows into its own buffers and adds the work and the counts to its own, so the frame
// and its counters come out as a local render would make them.

#include <functional>
#include <string>
#include <vector>

#include "core/counters.h"
#include "core/stage_ops.h"
#include "rasterizer/common/pixel_counters.h"
#include "rasterizer/common/transparent_layers.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

struct FrameRows {
    VisibilityBuffer* visibility = nullptr;
    TransparentLayers* transparent = nullptr;  // may be null
    PixelCounters* pixels = nullptr;           // may be null
    std::vector<PatchOps>* ops = nullptr;      // per patch
    CounterValues* counters = nullptr;  // packed: this rank's visibility counts; unpacked: merged
};

// Packs the pixel rows and tile rows for which the predicates hold.
std::string packFrameRows(const FrameRows& rows, const std::function<bool(int y)>& ownsPixelRow,
                          const std::function<bool(int ty)>& ownsTileRow);
// Copies packed rows into `rows` and adds the packed work to its work.
void unpackFrameRows(const std::string& bytes, const FrameRows& rows);

}  // namespace patchsim
