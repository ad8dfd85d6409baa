#include "rasterizer/verifier/tile_test_cases.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "core/enum_names.h"
#include "core/samples.h"

namespace patchsim {

namespace {

// Uniform floats from a hashed counter.
class CaseRandom {
  public:
    CaseRandom(std::uint64_t seed, CaseModel model, std::int64_t number)
        : state_(mix64(mix64(seed ^ (std::uint64_t(model) << 56)) ^ std::uint64_t(number))) {}
    float unit() {
        state_ = mix64(state_);
        return float(state_ >> 40) * (1.0f / 16777216.0f);
    }
    Vec3 unit3() { return {unit(), unit(), unit()}; }

  private:
    std::uint64_t state_;
};

// A tile of `size` pixels, grid-aligned, near raster position `at` (within 24 pixels).
TileRect tileNear(Vec2 at, int size, CaseRandom& random) {
    const int x = int(std::floor(at.x + (random.unit() - 0.5f) * 48.0f));
    const int y = int(std::floor(at.y + (random.unit() - 0.5f) * 48.0f));
    const auto align = [&](int v) { return v - ((v % size) + size) % size; };
    return {align(x), align(y), align(x) + size, align(y) + size};
}

// The world seen from a camera moved by a small turn about y and a small step.
Vec3 movedCamera(const Vec3& p, float turn, const Vec3& step) {
    const float c = std::cos(turn), s = std::sin(turn);
    const Vec3 q = p - step;
    return {c * q.x + s * q.z, q.y, -s * q.x + c * q.z};
}

void printFloat(std::ostream& out, const char* label, float v) {
    char text[96];
    std::snprintf(text, sizeof text, "%s %a (%.9g)", label, double(v), double(v));
    out << text;
}

void printBox(std::ostream& out, const char* label, const Box3& b) {
    out << "  " << label << ":";
    for (int k = 0; k < 3; ++k) printFloat(out, " lower", b.lower[k]);
    out << "\n   ";
    for (int k = 0; k < 3; ++k) printFloat(out, " upper", b.upper[k]);
    out << "\n";
}

void printLensAndTile(std::ostream& out, const LensModel& lens, const TileRect& tile) {
    out << "  lens:";
    printFloat(out, " radius", lens.radius);
    printFloat(out, " focus", lens.focusDistance);
    out << "\n  tile: pixels [" << tile.x0 << ", " << tile.x1 << ") x [" << tile.y0 << ", "
        << tile.y1 << ")\n";
}

}  // namespace

const Camera& verifierCamera() {
    static const Camera camera = [] {
        CameraDesc desc;
        desc.open = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
        desc.close = desc.open;
        desc.fovYDegrees = 60.0f;
        desc.nearPlane = 0.1f;
        desc.farPlane = 100.0f;
        return Camera(desc, {}, 128, 128);
    }();
    return camera;
}

namespace {

constexpr EnumName<BoxCaseKind> kBoxCaseKinds[] = {{BoxCaseKind::Still, "still"},
                                                   {BoxCaseKind::DepthOnly, "depth-only"},
                                                   {BoxCaseKind::Moving, "moving"},
                                                   {BoxCaseKind::CameraMotion, "camera-motion"}};

}  // namespace

const char* boxCaseKindName(BoxCaseKind kind) {
    return nameIn(kBoxCaseKinds, kind);
}

namespace {

constexpr EnumName<CaseFamily> kCaseFamilies[] = {
    {CaseFamily::Mixed, "mixed"},        {CaseFamily::NearPlane, "near-plane"},
    {CaseFamily::FarDepth, "far-depth"}, {CaseFamily::HugeMotion, "huge-motion"},
    {CaseFamily::Tiny, "tiny"},          {CaseFamily::Huge, "huge"},
    {CaseFamily::WideLens, "wide-lens"}};

// The box's depth, size, motion and lens pushed to the family's extreme; the mix's own draws are
// made first, so the mixed family's cases stay as they were.
void pushToFamily(CaseFamily family, CaseRandom& random, float& depth, Vec3& half, Vec3& motion,
                  LensModel& lens) {
    switch (family) {
        case CaseFamily::Mixed:
            break;
        case CaseFamily::NearPlane:  // the near plane is at 0.1
            depth = 0.02f + 0.3f * random.unit();
            half = random.unit3() * (0.005f + 0.1f * random.unit());
            break;
        case CaseFamily::FarDepth:  // the far plane is at 100
            depth = 60.0f + 45.0f * random.unit();
            break;
        case CaseFamily::HugeMotion:
            motion *= 20.0f;
            break;
        case CaseFamily::Tiny:  // a pixel is about 0.009 units wide per unit of depth
            half = random.unit3() * (1e-5f + 2e-3f * random.unit()) * depth;
            break;
        case CaseFamily::Huge:
            half = random.unit3() * (2.0f + 20.0f * random.unit());
            break;
        case CaseFamily::WideLens:
            if (lens.radius > 0)
                lens = {(0.3f + random.unit()) * depth, 0.3f + 20.0f * random.unit()};
            break;
    }
}

}  // namespace

const char* caseFamilyName(CaseFamily family) {
    return nameIn(kCaseFamilies, family);
}

bool parseCaseFamily(const std::string& name, CaseFamily& out) {
    return parseIn(kCaseFamilies, name, out);
}

std::string caseFamilyNames() {
    return namesIn(kCaseFamilies);
}

BoxCase makeBoxCase(std::uint64_t seed, CaseModel model, std::int64_t number, CaseFamily family) {
    CaseRandom random(seed, model, number);
    const Camera& camera = verifierCamera();
    BoxCase c;
    TileTestInput& in = c.input;
    in.camera = &camera;
    if (model == CaseModel::Lens)
        in.lens = {0.05f + 0.5f * random.unit(), 2.0f + 8.0f * random.unit()};
    // A box around a point in view, of random size, moving by a random amount (sometimes along a
    // plane, sometimes straight at the camera, sometimes not at all, sometimes only because the
    // camera moves).
    float depth = 1.0f + 12.0f * random.unit();
    const Vec2 across(random.unit() - 0.5f, random.unit() - 0.5f);
    Vec3 half = random.unit3() * (0.02f + 0.5f * random.unit());
    Vec3 motion = (random.unit3() - 0.5f) * (3.0f * random.unit());
    const int kind = int(random.unit() * 4.0f);  // moving twice as often as still or depth-only
    pushToFamily(family, random, depth, half, motion, in.lens);
    const Vec3 centre(across.x * depth, across.y * depth, -depth);
    c.kind = kind == 0   ? BoxCaseKind::Still
             : kind == 1 ? BoxCaseKind::DepthOnly
                         : BoxCaseKind::Moving;
    if (random.unit() < 0.2f) c.kind = BoxCaseKind::CameraMotion;
    in.box.bounds0 = {centre - half, centre + half};
    switch (c.kind) {
        case BoxCaseKind::Still:
            motion = Vec3(0);
            break;
        case BoxCaseKind::DepthOnly:
            motion = Vec3(0, 0, motion.z);
            break;
        case BoxCaseKind::Moving:
            break;
        case BoxCaseKind::CameraMotion: {
            // Still in the world: the camera turns and steps, so the camera-space box at t=1
            // bounds the corners as the moved camera sees them.
            const float turn = (random.unit() - 0.5f) * 0.4f;
            const Vec3 step = (random.unit3() - 0.5f) * 1.0f;
            Box3 seen;
            for (int k = 0; k < 8; ++k)
                seen.extend(movedCamera(in.box.bounds0.corner(k), turn, step));
            in.box.bounds1 = seen;
            motion =
                0.5f * ((seen.lower + seen.upper) - (in.box.bounds0.lower + in.box.bounds0.upper));
            break;
        }
    }
    if (c.kind != BoxCaseKind::CameraMotion)
        in.box.bounds1 = {centre - half + motion, centre + half + motion};
    // A tile near where the box is seen at t=0.5.
    Vec2 raster;
    camera.cameraToRaster(centre + 0.5f * motion, raster);
    in.tile = tileNear(raster, 4 << int(random.unit() * 3.0f), random);
    return c;
}

TileRect HierarchyCase::tile() const {
    const TileGrid grid{verifierCamera().width(), verifierCamera().height(), tileSize};
    return grid.rect(tileX, tileY);
}

void makeHierarchyCase(std::uint64_t seed, std::int64_t number, HierarchyCase& c) {
    CaseRandom random(seed, CaseModel::Hierarchy, number);
    const Camera& camera = verifierCamera();
    c.lens = random.unit() < 0.5f
                 ? LensModel{}
                 : LensModel{0.05f + 0.5f * random.unit(), 2.0f + 8.0f * random.unit()};
    const float depth = 1.5f + 10.0f * random.unit();
    const Vec3 centre((random.unit() - 0.5f) * depth, (random.unit() - 0.5f) * depth, -depth);
    const float size = 0.1f + 1.5f * random.unit();
    const Vec3 e1 = (random.unit3() - 0.5f) * size, e2 = (random.unit3() - 0.5f) * size;
    const Vec3 bend = (random.unit3() - 0.5f) * size;
    const Vec3 motion = (random.unit3() - 0.5f) * (2.0f * random.unit() * random.unit());
    const float jitter = 0.1f * random.unit();
    constexpr int kQuads = 4;
    c.mesh.clear();
    for (int j = 0; j <= kQuads; ++j) {
        for (int i = 0; i <= kQuads; ++i) {
            const float u = float(i) / kQuads, v = float(j) / kQuads;
            const Vec3 p = centre + (u - 0.5f) * e1 + (v - 0.5f) * e2 +
                           4.0f * u * (1 - u) * v * (1 - v) * bend;
            c.mesh.position0.push_back(p);
            c.mesh.position1.push_back(p + motion + (random.unit3() - 0.5f) * jitter * size);
            c.mesh.domain.push_back({u, v});
        }
    }
    for (std::uint32_t j = 0; j < kQuads; ++j) {
        for (std::uint32_t i = 0; i < kQuads; ++i) {
            const std::uint32_t a = j * (kQuads + 1) + i, b = a + 1, d = a + kQuads + 1, e = d + 1;
            for (std::uint32_t v : {a, b, e, a, e, d}) c.mesh.indices.push_back(v);
        }
    }
    std::vector<std::uint32_t> triangles(c.mesh.triangleCount());
    for (std::uint32_t t = 0; t < triangles.size(); ++t) triangles[t] = t;
    const int leafSize = 1 << int(random.unit() * 3.0f);  // 1, 2 or 4: 32, 16 or 8 leaves
    c.hierarchy.build(c.mesh, triangles.data(), triangles.size(), leafSize);
    c.tileSize = 4 << int(random.unit() * 3.0f);
    Vec2 raster;
    camera.cameraToRaster(centre + 0.5f * motion, raster);
    const TileRect near = tileNear(raster, c.tileSize, random);
    // On the tile grid, as the rasterizer's tiles are (the screen bounds are clamped to it).
    const TileGrid grid{camera.width(), camera.height(), c.tileSize};
    c.tileX = std::clamp(near.x0 / c.tileSize, 0, grid.tilesX() - 1);
    c.tileY = std::clamp(near.y0 / c.tileSize, 0, grid.tilesY() - 1);
}

bool parseCaseName(const std::string& name, CaseModel& model, std::int64_t& number) {
    const std::size_t colon = name.find(':');
    if (colon == std::string::npos) return false;
    const std::string tail = name.substr(colon + 1);
    if (!parseCaseModel(name.substr(0, colon), model) || tail.empty() || tail.size() > 15)
        return false;
    number = 0;
    for (char ch : tail) {
        if (ch < '0' || ch > '9') return false;
        number = number * 10 + (ch - '0');
    }
    return true;
}

std::string caseName(CaseModel model, std::int64_t number) {
    return std::string(caseModelName(model)) + ":" + std::to_string(number);
}

void printBoxCase(const BoxCase& c, std::ostream& out) {
    out << "  kind: " << boxCaseKindName(c.kind) << "\n";
    printLensAndTile(out, c.input.lens, c.input.tile);
    printBox(out, "box at t=0", c.input.box.bounds0);
    printBox(out, "box at t=1", c.input.box.bounds1);
}

void printHierarchyCase(const HierarchyCase& c, std::ostream& out) {
    printLensAndTile(out, c.lens, c.tile());
    out << "  tile size " << c.tileSize << ", tile (" << c.tileX << ", " << c.tileY << "), "
        << c.mesh.triangleCount() << " triangles, " << c.hierarchy.leafCount() << " leaves\n";
    for (int leaf = 0; leaf < c.hierarchy.leafCount(); ++leaf) {
        const LBBox& b = c.hierarchy.node(PatchHierarchy::firstLeaf(c.hierarchy.depth()) + leaf);
        char label[32];
        std::snprintf(label, sizeof label, "leaf %d at t=0", leaf);
        printBox(out, label, b.bounds0);
        std::snprintf(label, sizeof label, "leaf %d at t=1", leaf);
        printBox(out, label, b.bounds1);
    }
}

}  // namespace patchsim
