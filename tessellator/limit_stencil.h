#pragma once
// A limit stencil: the limit position and its two derivatives at one point of a subdivision
// surface, as weights on the cage vertices the surface depends on. Applying the same stencil to
// the control points at shutter open and at close gives the two ends of one surface point.

#include <vector>

namespace patchsim {

struct LimitStencil {
    std::vector<int> controlPoints;       // cage vertex of each weight
    std::vector<float> position, du, dv;  // weights
};

}  // namespace patchsim
