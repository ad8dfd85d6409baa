#include "core/scene_reader.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/obj_reader.h"
#include "core/text_file.h"

namespace patchsim {

namespace {

constexpr double kHuge = 1e30;

CameraKey readCameraKey(ObjectReader& r, const CameraKey& fallback) {
    CameraKey k;
    k.position = r.vec3("position", fallback.position);
    k.lookAt = r.vec3("look_at", fallback.lookAt);
    k.up = r.vec3("up", fallback.up);
    if (glm::length(k.lookAt - k.position) == 0.0f)
        r.fail(r.fieldName("look_at"), "must differ from position");
    if (glm::length(glm::cross(k.lookAt - k.position, k.up)) == 0.0f)
        r.fail(r.fieldName("up"), "must not be parallel to the view direction");
    return k;
}

void readCamera(ObjectReader r, CameraDesc& c) {
    c.open = readCameraKey(r, c.open);
    c.close = c.open;
    c.fovYDegrees = static_cast<float>(r.number("fov_y_degrees", c.fovYDegrees, 1e-3, 179.0));
    c.nearPlane = static_cast<float>(r.number("near", c.nearPlane, 1e-6, kHuge));
    c.farPlane = static_cast<float>(r.number("far", c.farPlane, 1e-6, kHuge));
    if (c.farPlane <= c.nearPlane) r.fail(r.fieldName("far"), "must be greater than near");
    if (auto close = r.object("close")) {
        c.close = readCameraKey(*close, c.open);
        close->finish();
    }
    r.finish();
}

void readLens(ObjectReader r, LensDesc& l) {
    l.apertureRadius = static_cast<float>(r.number("aperture_radius", l.apertureRadius, 0, kHuge));
    l.focusDistance = static_cast<float>(r.number("focus_distance", l.focusDistance, 1e-6, kHuge));
    r.finish();
}

void readShutter(ObjectReader r, ShutterDesc& s) {
    s.open = static_cast<float>(r.number("open", s.open, 0, 1));
    s.close = static_cast<float>(r.number("close", s.close, 0, 1));
    if (s.close < s.open) r.fail(r.fieldName("close"), "must not be before open");
    r.finish();
}

void readFilm(ObjectReader r, FilmDesc& f) {
    f.width = static_cast<int>(r.integer("width", f.width, 1, 16384));
    f.height = static_cast<int>(r.integer("height", f.height, 1, 16384));
    f.samplesPerPixel = static_cast<int>(r.integer("spp", f.samplesPerPixel, 1, 4096));
    f.seed = static_cast<std::uint64_t>(r.integer("seed", static_cast<std::int64_t>(f.seed), 0,
                                                  std::numeric_limits<std::int64_t>::max()));
    const std::string sampler = r.string("sampler", samplePatternName(f.sampler));
    if (!parseSamplePattern(sampler, f.sampler))
        r.fail(r.fieldName("sampler"),
               "unknown sampler '" + sampler + "' (stratified, grid, interleaved)");
    r.finish();
}

void readTessellation(ObjectReader r, TessellationDesc& t) {
    const std::string partitioning = r.string("partitioning", partitioningName(t.partitioning));
    if (!parsePartitioning(partitioning, t.partitioning)) {
        r.fail(r.fieldName("partitioning"),
               "unknown partitioning '" + partitioning +
                   "' (integer, pow2, fractional_odd, fractional_even)");
    }
    const std::string reduction =
        r.string("inside_reduction", insideReductionName(t.insideReduction));
    if (!parseInsideReduction(reduction, t.insideReduction))
        r.fail(r.fieldName("inside_reduction"),
               "unknown reduction '" + reduction + "' (min, max, average)");
    // Any finite factor is accepted: the hull shader and tessellator apply D3D11's rules
    // (<= 0 culls, the rest is clamped and rounded per partitioning).
    t.factor = static_cast<float>(r.number("factor", t.factor, -kHuge, kHuge));
    t.targetEdgePixels =
        static_cast<float>(r.number("target_edge_pixels", t.targetEdgePixels, 0, kHuge));
    t.maxFactor = static_cast<float>(r.number("max_factor", t.maxFactor, 1, 64));
    r.finish();
}

void readRasterizer(ObjectReader r, RasterizerOptions& o) {
    for (const RasterizerOptionField& field : rasterizerOptionFields()) {
        const Json* value = r.find(field.key);
        if (!value) continue;
        const std::string error = field.set(o, *value);
        if (!error.empty()) r.fail(r.fieldName(field.key), error);
    }
    r.finish();
    o.validate(r.file());
}

TransformDesc readTransform(ObjectReader r, const TransformDesc& fallback) {
    TransformDesc t;
    t.translate = r.vec3("translate", fallback.translate);
    t.rotateDegrees = r.vec3("rotate_degrees", fallback.rotateDegrees);
    t.scale = r.vec3("scale", fallback.scale);
    for (int i = 0; i < 3; ++i)
        if (t.scale[i] == 0.0f) r.fail(r.fieldName("scale"), "scale must not be zero");
    r.finish();
    return t;
}

SubdivisionScheme schemeFromCageName(const std::string& path) {
    const std::string name = std::filesystem::path(path).filename().string();
    if (name.starts_with("loop_")) return SubdivisionScheme::Loop;
    if (name.starts_with("bilinear_")) return SubdivisionScheme::Bilinear;
    return SubdivisionScheme::Catmark;
}

ObjectDesc readObject(ObjectReader r, const std::string& baseDir, std::size_t index) {
    ObjectDesc o;
    o.name = r.string("name", "object" + std::to_string(index));
    const std::string cage = r.requiredString("cage");
    if (cage.empty()) r.fail(r.fieldName("cage"), "must name an OBJ file");
    o.cagePath = joinPath(baseDir, cage);
    const std::string cageClose = r.string("cage_close", "");
    if (!cageClose.empty()) o.cageClosePath = joinPath(baseDir, cageClose);
    const std::string scheme = r.string("scheme", schemeName(schemeFromCageName(cage)));
    if (!parseScheme(scheme, o.scheme))
        r.fail(r.fieldName("scheme"), "unknown scheme '" + scheme + "' (" + schemeNames() + ")");
    if (auto open = r.object("open")) o.open = readTransform(*open, o.open);
    o.close = o.open;
    if (auto close = r.object("close")) o.close = readTransform(*close, o.open);
    if (auto material = r.object("material")) {
        o.material.color = material->vec3("color", o.material.color, 0, kHuge);
        o.material.opacity = static_cast<float>(material->number("opacity", 1.0, 0, 1));
        o.material.closeColor = o.material.color;
        o.material.closeOpacity = o.material.opacity;
        if (auto close = material->object("close")) {
            o.material.closeColor = close->vec3("color", o.material.color, 0, kHuge);
            o.material.closeOpacity =
                static_cast<float>(close->number("opacity", o.material.opacity, 0, 1));
            close->finish();
        }
        if (const Json* j = material->find("unlit")) {
            if (!j->is_boolean())
                material->fail(material->fieldName("unlit"),
                               "expected true or false, found " + typeName(*j));
            o.material.unlit = j->get<bool>();
        }
        material->finish();
    }
    r.finish();
    return o;
}

}  // namespace

void checkMemoryBudget(const FilmDesc& f, const SceneLimits& limits, const std::string& source,
                       const std::string& field) {
    if (filmBytes(f) <= limits.memoryBudgetBytes) return;
    throw InputError(source, field,
                     "film of " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                         " at " + std::to_string(f.samplesPerPixel) + " spp needs " +
                         std::to_string(filmBytes(f) >> 20) + " MiB, over the memory budget of " +
                         std::to_string(limits.memoryBudgetBytes >> 20) +
                         " MiB (--memory-budget-mib)");
}

std::uint64_t filmBytes(const FilmDesc& film) {
    constexpr std::uint64_t kBytesPerSample = 32;
    return std::uint64_t(film.width) * std::uint64_t(film.height) *
           std::uint64_t(film.samplesPerPixel) * kBytesPerSample;
}

SceneDesc parseScene(std::string_view text, const std::string& path, const std::string& baseDir,
                     const SceneLimits& limits) {
    const Json json = parseJson(text, path);
    SceneDesc scene;
    scene.path = path;
    ObjectReader root(json, "", path);
    if (auto camera = root.object("camera")) readCamera(*camera, scene.camera);
    if (auto lens = root.object("lens")) readLens(*lens, scene.lens);
    if (auto shutter = root.object("shutter")) readShutter(*shutter, scene.shutter);
    if (auto film = root.object("film")) readFilm(*film, scene.film);
    if (auto tess = root.object("tessellation")) readTessellation(*tess, scene.tessellation);
    if (auto raster = root.object("rasterizer")) readRasterizer(*raster, scene.rasterizer);
    const Json* objects = root.find("objects");
    if (!objects) root.fail("objects", "missing required array of objects");
    if (!objects->is_array())
        root.fail("objects", "expected an array, found " + typeName(*objects));
    if (objects->empty()) root.fail("objects", "the scene has no objects");
    for (std::size_t i = 0; i < objects->size(); ++i) {
        scene.objects.push_back(readObject(
            ObjectReader((*objects)[i], "objects[" + std::to_string(i) + "]", path), baseDir, i));
    }
    root.finish();
    checkMemoryBudget(scene.film, limits, path);
    return scene;
}

SceneDesc readSceneFile(const std::string& path, const SceneLimits& limits) {
    const std::string text = readTextFile(path);
    return parseScene(text, path, parentDirectory(path), limits);
}

SceneDesc sceneForCage(const std::string& objPath, const SceneLimits& limits) {
    const Cage cage = readObjCage(objPath);
    Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Vec3& p : cage.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const Vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    SceneDesc scene;
    scene.path = objPath;
    scene.camera.fovYDegrees = 40.0f;
    // Far enough that the bounding sphere fits the vertical field of view.
    const float distance = radius / std::sin(glm::radians(scene.camera.fovYDegrees) * 0.5f);
    scene.camera.open = {centre + Vec3(0, 0, distance), centre, {0, 1, 0}};
    scene.camera.close = scene.camera.open;
    scene.camera.nearPlane = std::max(1e-4f, 0.01f * radius);
    scene.camera.farPlane = distance + 10 * radius;
    scene.tessellation.factor = 4;
    ObjectDesc object;
    object.name = std::filesystem::path(objPath).stem().string();
    object.cagePath = objPath;
    object.scheme = schemeFromCageName(objPath);
    scene.objects.push_back(object);
    checkMemoryBudget(scene.film, limits, objPath, "film");
    return scene;
}

SceneDesc readSceneOrCage(const std::string& path, const SceneLimits& limits) {
    if (std::filesystem::path(path).extension() == ".obj") return sceneForCage(path, limits);
    return readSceneFile(path, limits);
}

SceneDesc defaultScene(const SceneLimits& limits) {
    const auto text = builtinAsset("default.json");
    if (!text) throw InputError("builtin:default.json", "", "built-in scene missing from build");
    return parseScene(*text, "builtin:default.json", "builtin:", limits);
}

}  // namespace patchsim
