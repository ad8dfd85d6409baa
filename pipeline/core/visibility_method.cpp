#include "pipeline/core/visibility_method.h"

namespace patchsim {

const std::vector<VisibilityMethodInfo>& visibilityMethods() {
    static const std::vector<VisibilityMethodInfo> methods = {
        {VisibilityMethod::Patch, "patch", true, "US 8,791,945: moving-box hierarchy per patch"},
        {VisibilityMethod::Reference, "reference", true,
         "every sample against every triangle: the oracle"},
        {VisibilityMethod::TriangleBBox, "triangle-bbox", true,
         "Akenine-Moller et al. 2007, McGuire et al. 2010: each triangle's bounds over the "
         "shutter"},
        {VisibilityMethod::Interval, "interval", true,
         "Fatahalian et al. 2009: time strata, per-stratum bounds"},
        {VisibilityMethod::Interleaved, "interleaved", false,
         "accumulation buffer: one time and lens point per sample index in every pixel"},
        {VisibilityMethod::Postprocess, "postprocess", false,
         "McGuire et al. 2012 reconstruction filter on a mid-shutter pinhole frame (weights as in "
         "Tan et al. 2022)"},
        {VisibilityMethod::Hybrid, "hybrid", false,
         "Tan et al. 2022: the post-process plus a ray mask and rays that reveal the background "
         "behind moving edges"},
        {VisibilityMethod::Reprojection, "reprojection", false,
         "Taylor: the samples of sharp frames at shutter open and close reprojected into cameras "
         "across the shutter (camera motion)"},
        {VisibilityMethod::TFragment, "tfragment", false,
         "Widmer et al. 2016: t-fragments rasterized at t=1, an LBVH of their t-AABBs, lens rays, "
         "motion sampling"},
    };
    return methods;
}

const VisibilityMethodInfo& methodInfo(VisibilityMethod m) {
    for (const VisibilityMethodInfo& info : visibilityMethods())
        if (info.method == m) return info;
    return visibilityMethods().front();
}

const char* visibilityMethodName(VisibilityMethod m) {
    return methodInfo(m).name;
}

bool parseVisibilityMethod(const std::string& name, VisibilityMethod& out) {
    for (const VisibilityMethodInfo& info : visibilityMethods()) {
        if (name == info.name) {
            out = info.method;
            return true;
        }
    }
    return false;
}

std::string visibilityMethodNames() {
    std::string names;
    for (const VisibilityMethodInfo& info : visibilityMethods())
        names += (names.empty() ? "" : ", ") + std::string(info.name);
    return names;
}

}  // namespace patchsim
