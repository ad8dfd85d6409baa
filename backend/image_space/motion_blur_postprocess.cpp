#include "backend/image_space/motion_blur_postprocess.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/counters.h"
#include "core/samples.h"

namespace patchsim {

namespace {

float saturate(float x) {
    return std::clamp(x, 0.0f, 1.0f);
}

float smoothstep(float a, float b, float x) {
    const float t = b > a ? saturate((x - a) / (b - a)) : (x >= b ? 1.0f : 0.0f);
    return t * t * (3.0f - 2.0f * t);
}

float cylinder(float v, float s) {
    return 1.0f - smoothstep(0.95f * v, 1.05f * v, s);
}

// 1 - s / v, saturated; a still pixel (v = 0) reaches nothing beyond itself.
float reach(float s, float v) {
    return v > 0.0f ? saturate(1.0f - s / v) : (s <= 0.0f ? 1.0f : 0.0f);
}

struct Velocities {
    int width = 0, height = 0;
    std::vector<Vec2> v;  // per pixel, half the exposure's motion, at most k long
    Vec2 at(int x, int y) const { return v[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

Velocities pixelVelocities(const ResolvedFrame& f, float k) {
    Velocities out{f.color.width, f.color.height, {}};
    out.v.resize(f.motionX.size());
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] = pixelVelocity(f, i, k);
    return out;
}

// The tile planes' masks in a trace (0: not recorded).
struct TilePlanes {
    ImagePassTrace* trace = nullptr;
    std::uint16_t velocity = 0, tileMax = 0, neighbourMax = 0;
};

// The longest velocity of each tile, then of each tile's 3 x 3 neighbourhood.
std::vector<Vec2> neighbourMax(const Velocities& v, int k, int tilesX, int tilesY,
                               PostprocessWork& work, const TilePlanes& planes) {
    ImagePassTrace* trace = planes.trace;
    if (trace) trace->beginPass("TileMax");
    std::vector<Vec2> tileMax(std::size_t(tilesX) * std::size_t(tilesY), Vec2(0));
    for (int y = 0; y < v.height; ++y) {
        for (int x = 0; x < v.width; ++x) {
            Vec2& m = tileMax[std::size_t(y / k) * std::size_t(tilesX) + std::size_t(x / k)];
            const Vec2 p = v.at(x, y);
            if (glm::dot(p, p) > glm::dot(m, m)) m = p;
            if (trace)
                trace->read(planes.velocity,
                            std::size_t(y) * std::size_t(v.width) + std::size_t(x));
        }
        if (trace && (y % k == k - 1 || y == v.height - 1))
            for (int tx = 0; tx < tilesX; ++tx)
                trace->write(planes.tileMax,
                             std::size_t(y / k) * std::size_t(tilesX) + std::size_t(tx));
    }
    work.pixels += std::int64_t(v.width) * v.height;
    std::vector<Vec2> out(tileMax.size(), Vec2(0));
    if (trace) trace->beginPass("NeighbourMax");
    for (int ty = 0; ty < tilesY; ++ty) {
        for (int tx = 0; tx < tilesX; ++tx) {
            const std::size_t tile = std::size_t(ty) * std::size_t(tilesX) + std::size_t(tx);
            Vec2& m = out[tile];
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = tx + dx, ny = ty + dy;
                    if (nx < 0 || ny < 0 || nx >= tilesX || ny >= tilesY) continue;
                    const std::size_t at = std::size_t(ny) * std::size_t(tilesX) + std::size_t(nx);
                    const Vec2 p = tileMax[at];
                    if (glm::dot(p, p) > glm::dot(m, m)) m = p;
                    if (trace) trace->read(planes.tileMax, at);
                }
            }
            if (trace) trace->write(planes.neighbourMax, tile);
        }
    }
    work.tiles += 2 * std::int64_t(tileMax.size());
    return out;
}

// The hybrid's split of one target pixel's gather (with a revealed background), beside the
// post-process's own sums. Coverage is counted, not weighted: a moving object covers the target
// for about the share of the span (the S samples along the velocity) that lies on it, where the
// filter's weights make it too opaque on both sides of its silhouette.
class Composite {
  public:
    // The target itself, the span's centre sample, of weight `a`.
    Composite(const RevealedBackground& r, std::size_t target, float a, Vec3 c)
        : r_(r), target_(target), object_(r.object[target]), restWeight_(a), restSum_(a * c) {
        if (object_ < 0) return;
        addOwn(target, a, c);
    }

    // Span sample j of weight `a`, colour `c`, velocity `vs`, at `s` pixels, `z` as the gather's.
    void add(std::size_t j, float a, Vec3 c, float z, float vs, float s) {
        if (object_ >= 0 && r_.object[j] == object_) addOwn(j, a, c);
        const float reaches = saturate(z) * cylinder(vs, s);  // in front, and moves over it
        front_ += reaches;
        frontRevealed_ += reaches * float(r_.found[j]);
        frontWeight_ += reaches * a;
        frontSum_ += reaches * a * c;
        restWeight_ += (1.0f - reaches) * a;
        restSum_ += (1.0f - reaches) * a * c;
    }

    // Inner blur, where rays revealed what is behind the target's object: its own samples over
    // that background. Outer blur, where they revealed what is behind the objects moving over
    // the target: those objects' samples over the rest of the gather. Either blended with the
    // post-process's `pp` by the share of those samples whose background was revealed, so the
    // ray mask's holes and edges are no seams; with no such sample, `pp` itself.
    Vec3 blend(Vec3 pp, int samples) const {
        if (ownRevealed_ > 0) {
            const float coverage = float(own_) / float(samples);
            const Vec3 behind =
                r_.found[target_] ? r_.color[target_] : revealedSum_ / float(ownRevealed_);
            const Vec3 hybrid = coverage * ownSum_ / ownWeight_ + (1.0f - coverage) * behind;
            return pp + (float(ownRevealed_) / float(own_)) * (hybrid - pp);
        }
        if (frontRevealed_ > 0 && frontWeight_ > 0) {
            const float coverage = std::min(1.0f, front_ / float(samples));
            const Vec3 hybrid =
                coverage * frontSum_ / frontWeight_ + (1.0f - coverage) * restSum_ / restWeight_;
            return pp + (frontRevealed_ / front_) * (hybrid - pp);
        }
        return pp;
    }

  private:
    void addOwn(std::size_t j, float a, Vec3 c) {
        ++own_;
        ownWeight_ += a;
        ownSum_ += a * c;
        if (!r_.found[j]) return;
        ++ownRevealed_;
        revealedSum_ += r_.color[j];
    }

    const RevealedBackground& r_;
    std::size_t target_;
    int object_;
    int own_ = 0, ownRevealed_ = 0;
    float ownWeight_ = 0, front_ = 0, frontRevealed_ = 0, frontWeight_ = 0, restWeight_;
    Vec3 ownSum_{0}, revealedSum_{0}, frontSum_{0}, restSum_;
};

}  // namespace

Vec2 pixelVelocity(const ResolvedFrame& f, std::size_t i, float k) {
    Vec2 v = 0.5f * Vec2(f.motionX[i], f.motionY[i]);
    const float len = glm::length(v);
    if (len > k) v *= k / len;
    return v;
}

PATCHSIM_WORK_DEFINE(PostprocessWork, PostprocessCounters, postprocessCounters,
                     PATCHSIM_POSTPROCESS_WORK)

PostprocessPlanes recordResolveAovs(ImagePassTrace& trace, int width, int height) {
    const auto pixels = std::uint64_t(width) * std::uint64_t(height);
    PostprocessPlanes planes{&trace, trace.addPlane("depth", pixels, kPlaneDepthBytes),
                             trace.addPlane("velocity", pixels, kPlaneVelocityBytes), 0};
    trace.beginPass("resolve AOVs");
    for (std::uint64_t i = 0; i < pixels; ++i)
        trace.write(std::uint16_t(planes.depth | planes.velocity), i);
    return planes;
}

Image reconstructMotionBlur(const ResolvedFrame& sharp, float farDepth, const PostprocessOptions& o,
                            PostprocessWork& work, const RevealedBackground* revealed,
                            const PostprocessPlanes& planes) {
    const int w = sharp.color.width, h = sharp.color.height, k = std::max(1, o.tileSize);
    const Velocities v = pixelVelocities(sharp, float(k));
    const int tilesX = (w + k - 1) / k, tilesY = (h + k - 1) / k;
    ImagePassTrace* trace = planes.trace;
    TilePlanes tiles{trace, planes.velocity};
    std::uint16_t output = 0;
    if (trace) {
        const auto tileCount = std::uint64_t(tilesX) * std::uint64_t(tilesY);
        tiles.tileMax = trace->addPlane("TileMax", tileCount, kPlaneVelocityBytes);
        tiles.neighbourMax = trace->addPlane("NeighbourMax", tileCount, kPlaneVelocityBytes);
        output = trace->addPlane("output", std::uint64_t(w) * std::uint64_t(h),
                                 kResolvedImagePixelBytes);
    }
    const std::vector<Vec2> vN = neighbourMax(v, k, tilesX, tilesY, work, tiles);
    const auto tap = std::uint16_t(ImagePassTrace::resolvedImage() | planes.depth |
                                   planes.velocity | planes.revealed);
    if (trace) trace->beginPass("gather");
    auto depth = [&](int x, int y) {
        const float z = sharp.depth[std::size_t(y) * std::size_t(w) + std::size_t(x)];
        return z > 0.0f ? z : farDepth;
    };
    Image out = sharp.color;
    const int S = std::max(3, o.samples | 1);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t tile = std::size_t(y / k) * std::size_t(tilesX) + std::size_t(x / k);
            const Vec2 n = vN[tile];
            const std::size_t target = std::size_t(y) * std::size_t(w) + std::size_t(x);
            if (trace) {
                trace->read(tiles.neighbourMax, tile);
                trace->read(ImagePassTrace::resolvedImage(), target);
            }
            if (glm::length(n) <= 0.5f) {
                if (trace) trace->write(output, target);
                continue;
            }
            ++work.blurredPixels;
            if (trace) trace->read(std::uint16_t(tap & ~ImagePassTrace::resolvedImage()), target);
            const float vt = glm::length(v.at(x, y)), zt = depth(x, y);
            float weight = 1.0f / std::max(vt, 1.0f);
            Vec3 sum = sharp.color.get(x, y) * weight;
            std::optional<Composite> composite;
            if (revealed) composite.emplace(*revealed, target, weight, sharp.color.get(x, y));
            const std::uint64_t hash =
                mix64(o.seed ^ mix64((std::uint64_t(x) << 32) | std::uint64_t(y)));
            const float jitter = float(hash >> 40) * (1.0f / 16777216.0f) - 0.5f;
            for (int i = 0; i < S; ++i) {
                if (i == (S - 1) / 2) continue;
                const float t = -1.0f + 2.0f * (float(i) + jitter + 1.0f) / float(S + 1);
                const int sx = std::clamp(int(std::floor(float(x) + n.x * t + 0.5f)), 0, w - 1);
                const int sy = std::clamp(int(std::floor(float(y) + n.y * t + 0.5f)), 0, h - 1);
                if (trace) trace->read(tap, std::size_t(sy) * std::size_t(w) + std::size_t(sx));
                const float s = glm::length(Vec2(float(sx - x), float(sy - y)));
                const float vs = glm::length(v.at(sx, sy));
                const float z = (zt - depth(sx, sy)) / o.softZExtent;
                const float wf = saturate(1.0f + z) * reach(s, vs);
                const float wb = saturate(1.0f - z) * reach(s, vt);
                const float ws = cylinder(vs, s) * cylinder(vt, s) * 2.0f;
                const float a = wf + wb + ws;
                weight += a;
                const Vec3 c = sharp.color.get(sx, sy);
                sum += a * c;
                if (composite)
                    composite->add(std::size_t(sy) * std::size_t(w) + std::size_t(sx), a, c, z, vs,
                                   s);
                ++work.gatherSamples;
            }
            out.set(x, y, composite ? composite->blend(sum / weight, S) : sum / weight);
            if (trace) trace->write(output, target);
        }
    }
    return out;
}

}  // namespace patchsim
