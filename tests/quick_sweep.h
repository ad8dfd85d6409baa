#pragma once
// A small `patchsim sweep` for tests of the approximate methods' claims: one scene, the given
// methods and samples per pixel, one repeat, a 64-spp converged image, no progress bar.

#include <sstream>
#include <string>
#include <vector>

#include "pipeline/driver/sweep.h"
#include "tests/test_paths.h"

namespace patchsim::test {

inline std::vector<SweepRow> quickSweep(const SceneDesc& scene,
                                        const std::vector<const VisibilityMethod*>& methods,
                                        std::vector<int> samplesPerPixel, const std::string& name,
                                        const RenderOptions& render = {}) {
    SweepOptions o;
    for (const VisibilityMethod* m : methods) o.variants.push_back({m, "", render, {}});
    o.samplesPerPixel = std::move(samplesPerPixel);
    o.repeats = 1;
    o.convergedSamplesPerPixel = 64;
    o.hardware = defaultHardwareConfig();
    o.outputDir = temporaryDirectory() + "/" + name;
    o.progress = false;
    o.render = render;
    std::ostringstream log;
    return runSweep({{name, scene}}, o, log);
}

}  // namespace patchsim::test
