#include "rasterizer/common/frame_partition.h"

namespace patchsim {

int FramePartition::bandOf(int y, int height) {
    for (int band = 0; band < kClasses; ++band)
        if (y < bandBegin(band + 1, height)) return band;
    return kClasses - 1;
}

}  // namespace patchsim
