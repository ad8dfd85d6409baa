#pragma once
// The tile-test verifier's random cases (docs/TILE_TESTS.md), each made from (seed, model,
// number) alone so that any one can be replayed.
//
// Representation
// --------------
// A box case is a TileTestInput (the verifier's fixed 128x128 camera, a lens for lens cases, a
// tile, a camera-space moving box) and its kind. A hierarchy case is a small moving triangle sheet
// (a 4x4 grid of quads on a random bilinear patch, bent and jittered, moving rigidly plus a
// per-vertex jitter) with its hierarchy, a tile of the tile grid it was placed on, and a lens.
// Random numbers come from a counter hashed with mix64, the same on every platform.

#include <cstdint>
#include <iosfwd>
#include <string>

#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/verifier/tile_test_variant.h"

namespace patchsim {

// The camera every case is seen by: at the origin looking down -z, 60 degrees, 128x128 pixels.
const Camera& verifierCamera();

enum class BoxCaseKind : std::uint8_t { Still, DepthOnly, Moving, CameraMotion };
const char* boxCaseKindName(BoxCaseKind kind);

struct BoxCase {
    TileTestInput input;
    BoxCaseKind kind = BoxCaseKind::Moving;
};

// A family of box cases (verify-tiles --family): the random mix, or one hard case pushed to its
// extreme: boxes at and across the near plane, near the far plane, moving tens of units, smaller
// than a pixel, larger than the view, or seen through an aperture as wide as their distance.
enum class CaseFamily : std::uint8_t {
    Mixed,
    NearPlane,
    FarDepth,
    HugeMotion,
    Tiny,
    Huge,
    WideLens
};
const char* caseFamilyName(CaseFamily family);
bool parseCaseFamily(const std::string& name, CaseFamily& out);
std::string caseFamilyNames();  // "mixed, near-plane, ..."

BoxCase makeBoxCase(std::uint64_t seed, CaseModel model, std::int64_t number,
                    CaseFamily family = CaseFamily::Mixed);

struct HierarchyCase {
    MovingMesh mesh;
    PatchHierarchy hierarchy;
    LensModel lens;
    int tileSize = 8, tileX = 0, tileY = 0;
    TileRect tile() const;
};

void makeHierarchyCase(std::uint64_t seed, std::int64_t number, HierarchyCase& out);

// "lens:1234" -> (Lens, 1234); false when not a case name.
bool parseCaseName(const std::string& name, CaseModel& model, std::int64_t& number);
std::string caseName(CaseModel model, std::int64_t number);

// The case's inputs, in hexadecimal floats (exact) and decimals.
void printBoxCase(const BoxCase& c, std::ostream& out);
void printHierarchyCase(const HierarchyCase& c, std::ostream& out);

}  // namespace patchsim
