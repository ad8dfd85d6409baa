#include "rasterizer/common/sample_rays.h"

namespace patchsim {

Ray sampleRay(const RayCaster& c, int x, int y, int s) {
    const Sample smp = c.samples.sample(x, y, s);
    const Vec2 screen = rasterToScreen(c.camera, Vec2(float(x), float(y)) + smp.pixelOffset);
    return makeCameraRay(c.camera, screen, concentricDisk(smp.lens), smp.time, c.lens);
}

}  // namespace patchsim
