#include "pipeline/driver/converged_image.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pipeline/core/output_set.h"
#include "pipeline/core/samples.h"
#include "pipeline/core/text_file.h"

namespace patchsim {

namespace {

constexpr int kSamplesPerPass = 64;

std::string text(const Vec3& v) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "%.9g %.9g %.9g", double(v.x), double(v.y), double(v.z));
    return buffer;
}
std::string text(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", v);
    return buffer;
}

void describe(std::ostream& out, const CameraKey& k) {
    out << text(k.position) << " / " << text(k.lookAt) << " / " << text(k.up) << "\n";
}
void describe(std::ostream& out, const TransformDesc& t) {
    out << text(t.translate) << " / " << text(t.rotateDegrees) << " / " << text(t.scale) << "\n";
}

}  // namespace

std::uint64_t contentHash(const std::string& s) {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a, 64 bits
    for (unsigned char c : s) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string convergedKey(const SceneDesc& scene, int spp, const RenderOptions& options) {
    std::ostringstream out;
    out << "patchsim converged image, image version " << kImageVersion << "\n"
        << "method patch, " << spp << " spp in passes of " << kSamplesPerPass << "\n"
        << "filter " << resolveFilterName(options.resolve.filter) << " "
        << text(options.resolve.gaussianSigma) << " " << text(options.resolve.gaussianRadius)
        << ", shading " << shadingRateName(options.resolve.shadingRate) << ", layers "
        << options.maxLayers << ", overrides " << options.overrides.disableMotion
        << options.overrides.disableDefocus << options.overrides.disableTransparency << "\n";
    const CameraDesc& c = scene.camera;
    out << "camera ";
    describe(out, c.open);
    out << "camera close ";
    describe(out, c.close);
    out << "fov near far " << text(c.fovYDegrees) << " " << text(c.nearPlane) << " "
        << text(c.farPlane) << "\n"
        << "lens " << text(scene.lens.apertureRadius) << " " << text(scene.lens.focusDistance)
        << "\nshutter " << text(scene.shutter.open) << " " << text(scene.shutter.close) << "\n"
        << "film " << scene.film.width << "x" << scene.film.height << " seed " << scene.film.seed
        << " sampler " << samplePatternName(scene.film.sampler) << "\n";
    const TessellationDesc& t = scene.tessellation;
    out << "tessellation " << partitioningName(t.partitioning) << " "
        << insideReductionName(t.insideReduction) << " " << text(t.factor) << " "
        << text(t.targetEdgePixels) << " " << text(t.maxFactor) << "\n";
    for (const ObjectDesc& o : scene.objects) {
        out << "object " << o.name << " " << schemeName(o.scheme) << "\n  open ";
        describe(out, o.open);
        out << "  close ";
        describe(out, o.close);
        const MaterialDesc& m = o.material;
        out << "  material " << text(m.color) << " " << text(m.opacity) << " / "
            << text(m.closeColor) << " " << text(m.closeOpacity) << " unlit " << m.unlit << "\n";
        for (const std::string& path : {o.cagePath, o.cageClosePath}) {
            if (path.empty()) continue;
            const std::string cage = readTextFile(path);
            char hash[17];
            std::snprintf(hash, sizeof hash, "%016llx",
                          static_cast<unsigned long long>(contentHash(cage)));
            out << "  cage " << path << " (" << cage.size() << " bytes, " << hash << ")\n";
        }
    }
    return out.str();
}

ConvergedImage convergedImage(const SceneDesc& scene, int spp, const RenderOptions& options,
                              const std::string& cacheDir) {
    namespace fs = std::filesystem;
    const std::string key = convergedKey(scene, spp, options);
    char name[17];
    std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(contentHash(key)));
    const std::string base = cacheDir + "/" + name;
    ConvergedImage result;
    result.path = base + ".exr";
    std::error_code ec;
    if (fs::exists(base + ".key", ec) && fs::exists(result.path, ec) &&
        readTextFile(base + ".key") == key) {
        result.color = readImage(result.path);
        result.coverage = readChannel(result.path, "coverage");
        result.fromCache = true;
        return result;
    }
    // Passes of at most 64 samples, each with its own seed; their average.
    const int passes = (spp + kSamplesPerPass - 1) / kSamplesPerPass;
    RenderOptions passOptions = options;
    passOptions.method = VisibilityMethod::Patch;
    passOptions.heatMaps = false;
    for (int p = 0; p < passes; ++p) {
        SceneDesc pass = scene;
        pass.film.samplesPerPixel = spp / passes + (p < spp % passes ? 1 : 0);
        pass.film.seed = mix64(scene.film.seed * 0x9e3779b97f4a7c15ull + std::uint64_t(p));
        const RenderResult r = renderScene(pass, passOptions);
        const float weight = float(pass.film.samplesPerPixel) / float(spp);
        if (p == 0) {
            result.color = Image(r.frame.color.width, r.frame.color.height);
            result.coverage.assign(r.frame.coverage.size(), 0.0f);
        }
        for (std::size_t i = 0; i < result.color.rgb.size(); ++i)
            result.color.rgb[i] += weight * r.frame.color.rgb[i];
        for (std::size_t i = 0; i < result.coverage.size(); ++i)
            result.coverage[i] += weight * r.frame.coverage[i];
    }
    OutputSet outputs;
    outputs.folder(cacheDir, "--converged-cache");
    const std::size_t pixels = result.coverage.size();
    std::vector<float> channels(pixels * 4);
    for (std::size_t p = 0; p < pixels; ++p) {
        for (std::size_t k = 0; k < 3; ++k) channels[4 * p + k] = result.color.rgb[3 * p + k];
        channels[4 * p + 3] = result.coverage[p];
    }
    writeFloatChannels(outputs.file(result.path, "--converged-cache"), result.color.width,
                       result.color.height, {"R", "G", "B", "coverage"}, channels);
    writePng(result.color, outputs.file(base + ".png", "--converged-cache"));
    outputs.writeText(base + ".key", "--converged-cache", [&](std::ostream& out) { out << key; });
    outputs.commit();
    return result;
}

}  // namespace patchsim
