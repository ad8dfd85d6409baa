#include "rasterizer/patent/raster_work.h"

#include <algorithm>

namespace patchsim {

PATCHSIM_WORK_DEFINE(RasterWork, RasterCounters, rasterCounters, PATCHSIM_RASTER_WORK)

const RatioCounter& sampleTestEfficiency() {
    static const RatioCounter ratio{"RS/Sample test efficiency",
                                    "Visibility samples per sample tested (DESIGN.md section 8)",
                                    visibilitySamplesCounter, samplesTestedCounter};
    return ratio;
}

}  // namespace patchsim
