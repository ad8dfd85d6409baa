#pragma once
// Options of the patch rasterizer (DESIGN.md section 4), documented in docs/SCENES.md.
//
// Representation
// --------------
// One plain struct, and one table of its fields: each field's JSON key (in a scene's "rasterizer"
// object and in an explore grid), its command-line flag, its help text and the one function that
// checks and sets it from a JSON value, and the one that reads it back. The scene reader, the
// command line and the explore grid all go through the table, so a value is accepted or refused by
// the same rule everywhere.

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/number_format.h"

namespace patchsim {

enum class BranchMethod : std::uint8_t { Root, FirstSplit, Bitmask };
const char* branchMethodName(BranchMethod m);
bool parseBranchMethod(const std::string& name, BranchMethod& out);

// Where the tile tests bound the moving boxes (US 8,791,945): 3D camera space, 2D homogeneous
// (X, Y, W) or 2D screen space (rasterizer/patent/projected_bounds.h).
enum class BoundsSpace : std::uint8_t { Camera3D, Homogeneous2D, Screen2D };
const char* boundsSpaceName(BoundsSpace s);
bool parseBoundsSpace(const std::string& name, BoundsSpace& out);

struct RasterizerOptions {
    int tileSize = 8;     // pixels per tile side
    int leafSize = 4;     // triangles per leaf
    int boundsLevel = 0;  // tree level whose boxes give the screen bounds
    BranchMethod branchMethod = BranchMethod::Bitmask;
    BoundsSpace boundsSpace = BoundsSpace::Camera3D;
    bool timeRefinement = true;  // narrow [tmin, tmax] at the leaves
    // With time refinement: narrow it at interior nodes too, so a subtree that is only near the
    // tile at other times is rejected without visiting its leaves (the patent narrows at leaves).
    bool interiorTimeRefinement = true;
    bool zCulling = true;  // tile far plane and ray tmax from the z-buffer
    // Larger patches are split into groups of at most this many triangles; 0: as many as a
    // hierarchy of 64 leaves holds (64 x leafSize), at most 256.
    int maxTrianglesPerGroup = 0;
    // Neighbouring patches (in scene order) of at most this many triangles each are merged into
    // one hierarchy, up to a group's worth; 0: never (every patch its own hierarchy).
    int mergeTrianglesBelow = 0;
    // The format the hierarchy's moving boxes are stored in (issue 35), each bound rounded
    // outward so a stored box holds the exact one: fp32 stores them as built.
    NumberFormat nodeFormat = NumberFormat::fp32();
    // The format the domain-shaded positions reach the rasterizer in (issue 35), rounded to
    // nearest: lossy, for every method alike (they share the meshes).
    NumberFormat vertexFormat = NumberFormat::fp32();
    // The arithmetic format of the tile planes' tests and the leaf time intervals (issue 35),
    // each distance bounded by running error analysis so no tile or time is rejected that exact
    // arithmetic on the fp32 planes accepts (rasterizer/patent/tile_frustum_rounded.h): 3D
    // bounds only.
    NumberFormat planeFormat = NumberFormat::fp32();
    // The format the 2D bounds space's projected nodes are stored in (issue 35), rounded outward
    // (fixed point in pixels, as D3D11's 16.8 snap; rasterizer/patent/projected_bounds_rounded.h):
    // bounds space 2d only.
    NumberFormat screenBoundsFormat = NumberFormat::fp32();
    // The arithmetic format of the per-sample ray-box tests (issue 35), each slab distance
    // bounded by running error analysis (rasterizer/patent/moving_box_ray_rounded.h).
    NumberFormat rayBoxFormat = NumberFormat::fp32();
    // The arithmetic format of the per-sample ray-triangle tests (issue 35), rounded to nearest:
    // lossy but watertight (rasterizer/common/watertight_triangle_rounded.h). The methods that
    // rasterize patches, and the reference; a static frame's edge-function test is D3D11's fixed
    // point already.
    NumberFormat triangleFormat = NumberFormat::fp32();

    int trianglesPerGroup() const;
    // Throws InputError(source, "rasterizer.max_triangles_per_group",
    // "rasterizer.plane_format" or "rasterizer.screen_bounds_format") when the fields disagree.
    void validate(const std::string& source) const;
    // Throws InputError(source, "rasterizer.tile_size") when a tile holds more samples than a
    // worker keeps (kMaxTileSamples).
    void validateTileSamples(int samplesPerPixel, const std::string& source) const;
};

// The most samples a tile may hold: each rasterizer worker keeps one tile's rays and the ray lists
// of a descent, about 500 bytes a sample (TileRays::bytesFor), so 2^20 is some 500 MiB a worker.
// A render also holds the film and every worker's scratch to the memory budget (render.cpp).
inline constexpr std::int64_t kMaxTileSamples = std::int64_t(1) << 20;

inline constexpr int kMaxLeavesPerHierarchy = 64;
// The most triangles a leaf holds (rasterizer.leaf_size's limit).
inline constexpr int kMaxLeafTriangles = 64;

struct RasterizerOptionField {
    const char* key;   // "tile_size"
    const char* flag;  // "--tile-size"
    const char* help;
    // Checks `value` and sets the field; returns an error message, empty when accepted.
    std::string (*set)(RasterizerOptions& options, const nlohmann::json& value);
    // The field's value as the text `set` accepts (stats.json records it).
    std::string (*get)(const RasterizerOptions& options);
};
const std::vector<RasterizerOptionField>& rasterizerOptionFields();
const RasterizerOptionField* findRasterizerOptionField(const std::string& key);

// A command-line or grid value as JSON: a number, true/false, or otherwise a string.
nlohmann::json optionValueFromText(const std::string& text);

}  // namespace patchsim
