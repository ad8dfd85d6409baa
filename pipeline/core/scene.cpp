#include "pipeline/core/scene.h"

#include <glm/gtc/matrix_transform.hpp>

namespace patchsim {

Mat4 TransformDesc::matrix() const {
    Mat4 m = glm::translate(Mat4(1.0f), translate);
    m = glm::rotate(m, glm::radians(rotateDegrees.z), Vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotateDegrees.y), Vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotateDegrees.x), Vec3(1, 0, 0));
    return glm::scale(m, scale);
}

const char* samplePatternName(SamplePattern p) {
    switch (p) {
        case SamplePattern::Stratified:
            return "stratified";
        case SamplePattern::Grid:
            return "grid";
        case SamplePattern::Interleaved:
            return "interleaved";
    }
    return "?";
}

bool parseSamplePattern(const std::string& name, SamplePattern& out) {
    for (SamplePattern p :
         {SamplePattern::Stratified, SamplePattern::Grid, SamplePattern::Interleaved}) {
        if (name == samplePatternName(p)) {
            out = p;
            return true;
        }
    }
    return false;
}

const char* schemeName(SubdivisionScheme s) {
    switch (s) {
        case SubdivisionScheme::Catmark:
            return "catmark";
        case SubdivisionScheme::Loop:
            return "loop";
        case SubdivisionScheme::Bilinear:
            return "bilinear";
    }
    return "?";
}

}  // namespace patchsim
