#pragma once
// The converged image a sweep measures error against (DESIGN.md section 9): an exact method (the
// patch method) at a high sample count, cached on disk.
//
// Representation
// --------------
// The image is the average of passes of at most 64 samples per pixel, each with its own seed (so
// memory stays that of one 64-sample frame however many samples it holds), with its coverage AOV.
// The cache key is a text naming everything that changes the image: patchsim's image version,
// every field of the scene description, the text of each cage it reads, the converged sample
// count and the method's options. Files are `<dir>/<hash>.exr` (RGB and coverage), `.png` and
// `.key` (the key text, then a line with a hash of the EXR's pixels): a cached image is reused
// only when its key text equals the wanted one byte for byte (so a stale image of another scene,
// an edited cage or another patchsim never is), and when the EXR reads back whole, at the film's
// size, with its four channels, and its pixels hash to the recorded value. Anything else (a
// truncated or edited file, one of another size) is rendered again and the reason noted.

#include <string>

#include "backend/images/image.h"
#include "pipeline/driver/render.h"

namespace patchsim {

// Changes whenever a change to patchsim changes rendered images.
inline constexpr int kImageVersion = 1;

// The converged image is rendered in passes of at most this many samples per pixel.
inline constexpr int kConvergedSamplesPerPass = 64;

struct ConvergedImage {
    Image color;
    std::vector<float> coverage;
    bool fromCache = false;
    std::string path;  // the cached EXR
    std::string note;  // why a cached image was not reused, when one was there
};

// Every image-relevant setting, as text.
std::string convergedKey(const SceneDesc& scene, int samplesPerPixel, const RenderOptions& options);
std::uint64_t contentHash(const std::string& text);

// From `cacheDir` when its key matches; else rendered and stored there.
ConvergedImage convergedImage(const SceneDesc& scene, int samplesPerPixel,
                              const RenderOptions& options, const std::string& cacheDir);

}  // namespace patchsim
