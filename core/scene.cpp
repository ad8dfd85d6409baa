#include "core/scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include "core/enum_names.h"

namespace patchsim {

Mat4 TransformDesc::matrix() const {
    Mat4 m = glm::translate(Mat4(1.0f), translate);
    m = glm::rotate(m, glm::radians(rotateDegrees.z), Vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotateDegrees.y), Vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotateDegrees.x), Vec3(1, 0, 0));
    return glm::scale(m, scale);
}

namespace {

constexpr EnumName<SamplePattern> kSamplePatterns[] = {{SamplePattern::Stratified, "stratified"},
                                                       {SamplePattern::Grid, "grid"},
                                                       {SamplePattern::Interleaved, "interleaved"}};
constexpr EnumName<SubdivisionScheme> kSchemes[] = {{SubdivisionScheme::Catmark, "catmark"},
                                                    {SubdivisionScheme::Loop, "loop"},
                                                    {SubdivisionScheme::Bilinear, "bilinear"}};

}  // namespace

const char* samplePatternName(SamplePattern p) {
    return nameIn(kSamplePatterns, p);
}
bool parseSamplePattern(const std::string& name, SamplePattern& out) {
    return parseIn(kSamplePatterns, name, out);
}

const char* schemeName(SubdivisionScheme s) {
    return nameIn(kSchemes, s);
}
bool parseScheme(std::string_view name, SubdivisionScheme& out) {
    return parseIn(kSchemes, name, out);
}
std::string schemeNames() {
    return namesIn(kSchemes);
}

}  // namespace patchsim
