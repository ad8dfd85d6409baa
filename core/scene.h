#pragma once
// The scene description, as read from a scene JSON file (docs/SCENES.md).
//
// Representation
// --------------
// Plain values only: the camera and every object are given by two keyframes, one at shutter
// open (t=0) and one at shutter close (t=1); everything between is linear. Object transforms are
// translate / rotate (XYZ Euler degrees) / scale, composed as T * Rz * Ry * Rx * S. A cage may
// also carry its own vertex positions at t=1 (`cage_close`, same topology). Paths are stored
// resolved against the scene file's folder. Nothing here knows about OpenSubdiv or the pipeline.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "core/rasterizer_options.h"
#include "core/tessellation_modes.h"

namespace patchsim {

struct CameraKey {
    Vec3 position{0, 0, 5};
    Vec3 lookAt{0, 0, 0};
    Vec3 up{0, 1, 0};
};

struct CameraDesc {
    CameraKey open;
    CameraKey close;  // equal to open unless the scene gives "close"
    float fovYDegrees = 40.0f;
    float nearPlane = 0.01f;
    float farPlane = 1000.0f;
};

struct LensDesc {
    float apertureRadius = 0.0f;  // world units; 0 is a pinhole
    float focusDistance = 5.0f;   // world units along the view direction
};

// The shutter is open for this part of the keyframe interval [0, 1]; the vertex stage re-keys
// the motion so that t=0 and t=1 are the shutter's opening and closing.
struct ShutterDesc {
    float open = 0.0f;
    float close = 1.0f;
};

// How samples are placed (core/samples.h explains each).
enum class SamplePattern : std::uint8_t { Stratified, Grid, Interleaved };
const char* samplePatternName(SamplePattern p);
bool parseSamplePattern(const std::string& name, SamplePattern& out);

struct FilmDesc {
    int width = 320;
    int height = 240;
    int samplesPerPixel = 16;
    std::uint64_t seed = 1;
    SamplePattern sampler = SamplePattern::Stratified;
};

struct TessellationDesc {
    Partitioning partitioning = Partitioning::Integer;
    InsideReduction insideReduction = InsideReduction::Average;
    float factor = 8.0f;            // used when targetEdgePixels is 0
    float targetEdgePixels = 0.0f;  // > 0: adaptive factors
    float maxFactor = 64.0f;        // cap on adaptive factors
};

struct TransformDesc {
    Vec3 translate{0, 0, 0};
    Vec3 rotateDegrees{0, 0, 0};
    Vec3 scale{1, 1, 1};
    Mat4 matrix() const;
};

enum class SubdivisionScheme : std::uint8_t { Catmark, Loop, Bilinear };
const char* schemeName(SubdivisionScheme s);
bool parseScheme(std::string_view name, SubdivisionScheme& out);
std::string schemeNames();  // "catmark, loop, bilinear"

// Colour and opacity at shutter open, and (`close`) at shutter close; a t-fragment blends them
// at its time. An unlit material shows its colour as is (no lighting, no texture).
struct MaterialDesc {
    Vec3 color{0.8f, 0.8f, 0.8f};
    float opacity = 1.0f;
    Vec3 closeColor{0.8f, 0.8f, 0.8f};
    float closeOpacity = 1.0f;
    bool unlit = false;
};

struct ObjectDesc {
    std::string name;
    std::string cagePath;       // resolved path of the OBJ control cage
    std::string cageClosePath;  // optional: positions at shutter close, same topology
    SubdivisionScheme scheme = SubdivisionScheme::Catmark;
    TransformDesc open;
    TransformDesc close;
    MaterialDesc material;
};

struct SceneDesc {
    std::string path;  // the file it came from ("<default>" for the built-in scene)
    CameraDesc camera;
    LensDesc lens;
    ShutterDesc shutter;
    FilmDesc film;
    TessellationDesc tessellation;
    RasterizerOptions rasterizer;
    std::vector<ObjectDesc> objects;
};

}  // namespace patchsim
