// The registry of visibility methods: one line per method (its factory, defined in its own file
// of this folder), in the order the help and the docs list them.

#include "pipeline/methods/visibility_method.h"

namespace patchsim {

const VisibilityMethod& patchMethod();
const VisibilityMethod& referenceMethod();
const VisibilityMethod& triangleBBoxMethod();
const VisibilityMethod& intervalMethod();
const VisibilityMethod& interleavedMethod();
const VisibilityMethod& postprocessMethod();
const VisibilityMethod& hybridMethod();
const VisibilityMethod& reprojectionMethod();
const VisibilityMethod& tfragmentMethod();

const std::vector<const VisibilityMethod*>& visibilityMethods() {
    static const std::vector<const VisibilityMethod*> methods = {
        &patchMethod(),    &referenceMethod(),    &triangleBBoxMethod(),
        &intervalMethod(), &interleavedMethod(),  &postprocessMethod(),
        &hybridMethod(),   &reprojectionMethod(), &tfragmentMethod(),
    };
    return methods;
}

}  // namespace patchsim
