#include "core/rasterizer_options.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/enum_names.h"
#include "core/error.h"

namespace patchsim {

using Json = nlohmann::json;

namespace {

constexpr EnumName<BranchMethod> kBranchMethods[] = {{BranchMethod::Root, "root"},
                                                     {BranchMethod::FirstSplit, "first-split"},
                                                     {BranchMethod::Bitmask, "bitmask"}};

constexpr EnumName<BoundsSpace> kBoundsSpaces[] = {{BoundsSpace::Camera3D, "3d"},
                                                   {BoundsSpace::Homogeneous2D, "2dh"},
                                                   {BoundsSpace::Screen2D, "2d"}};

}  // namespace

const char* boundsSpaceName(BoundsSpace s) {
    return nameIn(kBoundsSpaces, s);
}
bool parseBoundsSpace(const std::string& name, BoundsSpace& out) {
    return parseIn(kBoundsSpaces, name, out);
}

const char* branchMethodName(BranchMethod m) {
    return nameIn(kBranchMethods, m);
}
bool parseBranchMethod(const std::string& name, BranchMethod& out) {
    return parseIn(kBranchMethods, name, out);
}

int RasterizerOptions::trianglesPerGroup() const {
    return maxTrianglesPerGroup > 0 ? maxTrianglesPerGroup
                                    : std::min(256, kMaxLeavesPerHierarchy * leafSize);
}

void RasterizerOptions::validate(const std::string& source) const {
    if (trianglesPerGroup() > kMaxLeavesPerHierarchy * leafSize)
        throw InputError(source, "rasterizer.max_triangles_per_group",
                         std::to_string(maxTrianglesPerGroup) + " is more than a hierarchy of 64 " +
                             "leaves of " + std::to_string(leafSize) + " holds (at most " +
                             std::to_string(kMaxLeavesPerHierarchy * leafSize) + ")");
    if (planeFormat != NumberFormat::fp32() && boundsSpace != BoundsSpace::Camera3D)
        throw InputError(source, "rasterizer.plane_format",
                         formatName(planeFormat) + " needs bounds_space " +
                             boundsSpaceName(BoundsSpace::Camera3D) + " (the format computes " +
                             "the 3D tile planes' tests), not " + boundsSpaceName(boundsSpace));
    if (screenBoundsFormat != NumberFormat::fp32() && boundsSpace != BoundsSpace::Screen2D)
        throw InputError(source, "rasterizer.screen_bounds_format",
                         formatName(screenBoundsFormat) + " needs bounds_space " +
                             boundsSpaceName(BoundsSpace::Screen2D) + " (the format stores " +
                             "the 2D bounds space's projected nodes), not " +
                             boundsSpaceName(boundsSpace));
}

void RasterizerOptions::validateTileSamples(int samplesPerPixel, const std::string& source) const {
    const std::int64_t samples =
        std::int64_t(tileSize) * std::int64_t(tileSize) * std::int64_t(samplesPerPixel);
    if (samples <= kMaxTileSamples) return;
    throw InputError(source, "rasterizer.tile_size",
                     "a tile of " + std::to_string(tileSize) + "x" + std::to_string(tileSize) +
                         " pixels at " + std::to_string(samplesPerPixel) + " spp holds " +
                         std::to_string(samples) + " samples; the rasterizer keeps at most " +
                         std::to_string(kMaxTileSamples) +
                         " per tile in each worker's memory: use smaller tiles");
}

namespace {

std::string describe(const Json& j) {
    if (!j.is_string()) return j.dump();
    std::string quoted(1, '\'');
    quoted.append(j.get<std::string>()).push_back('\'');
    return quoted;
}

// A number format's name (core/number_format.h), or an error message.
std::string numberFormat(const Json& j, NumberFormat& out) {
    if (j.is_string() && parseNumberFormat(j.get<std::string>(), out)) return {};
    return "unknown number format " + describe(j) +
           " (fp32, fp16, bf16, or fixedI.F with I in 2..32, F in 0..30, I + F <= 48)";
}

// An integer in [lo, hi] (a JSON number without fraction), or an error message.
std::string integerIn(const Json& j, int lo, int hi, int& out) {
    if (!j.is_number_integer())
        return "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
               "], found " + describe(j);
    const auto v =
        j.is_number_unsigned()
            ? std::int64_t(std::min<std::uint64_t>(j.get<std::uint64_t>(), std::uint64_t(1) << 62))
            : j.get<std::int64_t>();
    if (v < lo || v > hi)
        return "value " + std::to_string(v) + " is outside [" + std::to_string(lo) + ", " +
               std::to_string(hi) + "]";
    out = int(v);
    return {};
}

std::string booleanText(bool b) {
    return b ? "true" : "false";
}

std::string boolean(const Json& j, bool& out) {
    if (!j.is_boolean()) return "expected true or false, found " + describe(j);
    out = j.get<bool>();
    return {};
}

const std::vector<RasterizerOptionField> kFields = {
    {"tile_size", "--tile-size", "Tile side in pixels (1..256)",
     [](RasterizerOptions& o, const Json& j) { return integerIn(j, 1, 256, o.tileSize); },
     [](const RasterizerOptions& o) { return std::to_string(o.tileSize); }},
    {"leaf_size", "--leaf-size", "Triangles per hierarchy leaf (1..64)",
     [](RasterizerOptions& o, const Json& j) {
         return integerIn(j, 1, kMaxLeafTriangles, o.leafSize);
     },
     [](const RasterizerOptions& o) { return std::to_string(o.leafSize); }},
    {"bounds_level", "--bounds-level",
     "Hierarchy level whose boxes give the screen bounds (0 = root .. 6)",
     [](RasterizerOptions& o, const Json& j) { return integerIn(j, 0, 6, o.boundsLevel); },
     [](const RasterizerOptions& o) { return std::to_string(o.boundsLevel); }},
    {"branch_method", "--branch-method", "Where rays start: root, first-split or bitmask",
     [](RasterizerOptions& o, const Json& j) -> std::string {
         if (j.is_string() && parseBranchMethod(j.get<std::string>(), o.branchMethod)) return {};
         return "unknown branch method " + describe(j) + " (root, first-split, bitmask)";
     },
     [](const RasterizerOptions& o) { return std::string(branchMethodName(o.branchMethod)); }},
    {"bounds_space", "--bounds-space",
     "Bounds of the tile tests: 3d (camera space), 2dh (homogeneous) or 2d (screen space)",
     [](RasterizerOptions& o, const Json& j) -> std::string {
         if (j.is_string() && parseBoundsSpace(j.get<std::string>(), o.boundsSpace)) return {};
         return "unknown bounds space " + describe(j) + " (" + namesIn(kBoundsSpaces) + ")";
     },
     [](const RasterizerOptions& o) { return std::string(boundsSpaceName(o.boundsSpace)); }},
    {"time_refinement", "--time-refinement",
     "Narrow each tile's time interval at the leaves (true/false)",
     [](RasterizerOptions& o, const Json& j) { return boolean(j, o.timeRefinement); },
     [](const RasterizerOptions& o) { return booleanText(o.timeRefinement); }},
    {"interior_time_refinement", "--interior-time-refinement",
     "With time refinement, narrow the time interval at interior nodes too (true/false)",
     [](RasterizerOptions& o, const Json& j) { return boolean(j, o.interiorTimeRefinement); },
     [](const RasterizerOptions& o) { return booleanText(o.interiorTimeRefinement); }},
    {"z_culling", "--z-culling", "Cull against the z-buffer (true/false)",
     [](RasterizerOptions& o, const Json& j) { return boolean(j, o.zCulling); },
     [](const RasterizerOptions& o) { return booleanText(o.zCulling); }},
    {"max_triangles_per_group", "--max-triangles-per-group",
     "Split larger patches into groups of at most this many triangles (0: 64 leaves' worth)",
     [](RasterizerOptions& o, const Json& j) {
         return integerIn(j, 0, 64 * 64, o.maxTrianglesPerGroup);
     },
     [](const RasterizerOptions& o) { return std::to_string(o.maxTrianglesPerGroup); }},
    {"merge_triangles_below", "--merge-triangles-below",
     "Merge neighbouring patches of at most this many triangles into one hierarchy (0: never)",
     [](RasterizerOptions& o, const Json& j) {
         return integerIn(j, 0, 64 * 64, o.mergeTrianglesBelow);
     },
     [](const RasterizerOptions& o) { return std::to_string(o.mergeTrianglesBelow); }},
    {"node_format", "--node-format",
     "Format of the hierarchy's stored boxes, rounded outward: fp32, fp16, bf16 or fixedI.F",
     [](RasterizerOptions& o, const Json& j) { return numberFormat(j, o.nodeFormat); },
     [](const RasterizerOptions& o) { return formatName(o.nodeFormat); }},
    {"vertex_format", "--vertex-format",
     "Format of the domain-shaded positions the rasterizer receives, rounded to nearest (lossy, "
     "every method): fp32, fp16, bf16 or fixedI.F",
     [](RasterizerOptions& o, const Json& j) { return numberFormat(j, o.vertexFormat); },
     [](const RasterizerOptions& o) { return formatName(o.vertexFormat); }},
    {"plane_format", "--plane-format",
     "Arithmetic format of the 3D tile planes' tests and leaf time intervals, each bounded by "
     "its rounding error (conservative; bounds space 3d only): fp32, fp16, bf16 or fixedI.F",
     [](RasterizerOptions& o, const Json& j) { return numberFormat(j, o.planeFormat); },
     [](const RasterizerOptions& o) { return formatName(o.planeFormat); }},
    {"screen_bounds_format", "--screen-bounds-format",
     "Format of the 2D bounds space's projected nodes, rounded outward (conservative; fixed point "
     "in pixels; bounds space 2d only): fp32, fp16, bf16 or fixedI.F",
     [](RasterizerOptions& o, const Json& j) { return numberFormat(j, o.screenBoundsFormat); },
     [](const RasterizerOptions& o) { return formatName(o.screenBoundsFormat); }},
    {"ray_box_format", "--ray-box-format",
     "Arithmetic format of the per-sample ray-box tests, each slab distance bounded by its "
     "rounding error (conservative): fp32, fp16, bf16 or fixedI.F",
     [](RasterizerOptions& o, const Json& j) { return numberFormat(j, o.rayBoxFormat); },
     [](const RasterizerOptions& o) { return formatName(o.rayBoxFormat); }},
    {"triangle_format", "--triangle-format",
     "Arithmetic format of the per-sample ray-triangle tests, rounded to nearest (lossy, "
     "watertight; the methods that rasterize patches, and the reference): fp32, fp16, bf16 or "
     "fixedI.F",
     [](RasterizerOptions& o, const Json& j) { return numberFormat(j, o.triangleFormat); },
     [](const RasterizerOptions& o) { return formatName(o.triangleFormat); }},
};

}  // namespace

const std::vector<RasterizerOptionField>& rasterizerOptionFields() {
    return kFields;
}

const RasterizerOptionField* findRasterizerOptionField(const std::string& key) {
    for (const RasterizerOptionField& f : kFields)
        if (key == f.key) return &f;
    return nullptr;
}

Json optionValueFromText(const std::string& text) {
    if (text == "true") return true;
    if (text == "false") return false;
    const Json number = Json::parse(text, nullptr, /*allow_exceptions=*/false);
    return number.is_number() ? number : Json(text);
}

}  // namespace patchsim
