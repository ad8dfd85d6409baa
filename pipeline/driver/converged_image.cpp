#include "pipeline/driver/converged_image.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/output_set.h"
#include "core/samples.h"
#include "core/text_file.h"
#include "pipeline/methods/visibility_method.h"

namespace patchsim {

namespace {

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
        << "method patch, " << spp << " spp in passes of " << kConvergedSamplesPerPass << "\n"
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

namespace {

// RGB then coverage, as the EXR stores them: what the `.key` file's pixel line hashes.
std::uint64_t pixelHash(const ConvergedImage& image) {
    std::string bytes(reinterpret_cast<const char*>(image.color.rgb.data()),
                      image.color.rgb.size() * sizeof(float));
    bytes.append(reinterpret_cast<const char*>(image.coverage.data()),
                 image.coverage.size() * sizeof(float));
    return contentHash(bytes);
}

std::string pixelLine(std::uint64_t hash) {
    char line[40];
    std::snprintf(line, sizeof line, "pixels %016llx\n", static_cast<unsigned long long>(hash));
    return line;
}

// Passes of at most kConvergedSamplesPerPass samples, each with its own seed; their average.
ConvergedImage renderConverged(const SceneDesc& scene, int spp, const RenderOptions& options) {
    ConvergedImage result;
    const int passes = (spp + kConvergedSamplesPerPass - 1) / kConvergedSamplesPerPass;
    RenderOptions passOptions = options;
    passOptions.method = &methodNamed("patch");
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
    return result;
}

// The option errors about the cache name: the cache is the folder "converged" in the sweep's
// output folder, so the option that chose it is the sweep's -o.
constexpr const char* kCacheField = "-o";

void storeConverged(const ConvergedImage& image, const std::string& base, const std::string& key,
                    const std::string& cacheDir) {
    OutputSet outputs;
    outputs.folder(cacheDir, kCacheField);
    const std::size_t pixels = image.coverage.size();
    std::vector<float> channels(pixels * 4);
    for (std::size_t p = 0; p < pixels; ++p) {
        for (std::size_t k = 0; k < 3; ++k) channels[4 * p + k] = image.color.rgb[3 * p + k];
        channels[4 * p + 3] = image.coverage[p];
    }
    writeFloatChannels(outputs.file(image.path, kCacheField), image.color.width, image.color.height,
                       {"R", "G", "B", "coverage"}, channels);
    writePng(image.color, outputs.file(base + ".png", kCacheField));
    outputs.writeText(base + ".key", kCacheField,
                      [&](std::ostream& out) { out << key << pixelLine(pixelHash(image)); });
    outputs.commit();
}

// The cached image when the cache holds a whole, matching one; else why not (in `note`).
bool readCached(const std::string& base, const std::string& key, const FilmDesc& film,
                ConvergedImage& result) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(base + ".key", ec) || !fs::exists(result.path, ec)) return false;
    // Only regular files are read (through links): opening a FIFO waits for a writer that never
    // comes, and a device such as /dev/zero never ends, so either would hang the sweep. Whatever
    // else is there is replaced by a fresh render (OutputSet renames over the entry itself).
    for (const std::string& path : {base + ".key", result.path}) {
        if (!fs::is_regular_file(path, ec)) {
            result.note = "the cached '" + path + "' is not a regular file";
            return false;
        }
    }
    const std::string recorded = readTextFile(base + ".key");
    if (recorded.compare(0, key.size(), key) != 0) return false;  // another image's key
    try {
        const std::vector<std::string> channels = readChannelNames(result.path);
        for (const char* name : {"R", "G", "B", "coverage"})
            if (std::find(channels.begin(), channels.end(), name) == channels.end())
                throw std::runtime_error(std::string("no channel ") + name);
        result.color = readImage(result.path);
        result.coverage = readChannel(result.path, "coverage");
    } catch (const std::exception& e) {
        result.note = std::string("the cached image did not read back: ") + e.what();
        return false;
    }
    if (result.color.width != film.width || result.color.height != film.height) {
        result.note = "the cached image is " + std::to_string(result.color.width) + "x" +
                      std::to_string(result.color.height) + ", not " + std::to_string(film.width) +
                      "x" + std::to_string(film.height);
        return false;
    }
    if (recorded.substr(key.size()) != pixelLine(pixelHash(result))) {
        result.note = "the cached image's pixels do not match their recorded hash";
        return false;
    }
    return true;
}

}  // namespace

ConvergedImage convergedImage(const SceneDesc& scene, int spp, const RenderOptions& options,
                              const std::string& cacheDir) {
    const std::string key = convergedKey(scene, spp, options);
    char name[17];
    std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(contentHash(key)));
    const std::string base = joinOutputPath(cacheDir, name);
    ConvergedImage result;
    result.path = base + ".exr";
    if (readCached(base, key, scene.film, result)) {
        result.fromCache = true;
        return result;
    }
    const std::string note = result.note;
    result = renderConverged(scene, spp, options);
    result.path = base + ".exr";
    result.note = note;
    storeConverged(result, base, key, cacheDir);
    return result;
}

}  // namespace patchsim
