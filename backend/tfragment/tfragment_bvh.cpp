#include "backend/tfragment/tfragment_bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace patchsim {

namespace {

std::uint32_t spreadBits(std::uint32_t v) {  // 10 bits to every third of 30
    v = (v * 0x00010001u) & 0xFF0000FFu;
    v = (v * 0x00000101u) & 0x0F00F00Fu;
    v = (v * 0x00000011u) & 0xC30C30C3u;
    v = (v * 0x00000005u) & 0x49249249u;
    return v;
}

std::uint32_t morton(const Vec3& unit) {
    auto q = [](float x) { return std::uint32_t(std::clamp(x * 1024.0f, 0.0f, 1023.0f)); };
    return (spreadBits(q(unit.x)) << 2) | (spreadBits(q(unit.y)) << 1) | spreadBits(q(unit.z));
}

// An orthonormal basis across direction d (Frisvad's, with Duff et al.'s fix).
void basisAcross(const Vec3& d, Vec3& e1, Vec3& e2) {
    const float sign = std::copysign(1.0f, d.z);
    const float a = -1.0f / (sign + d.z), b = d.x * d.y * a;
    e1 = Vec3(1.0f + sign * d.x * d.x * a, sign * b, -sign * d.x);
    e2 = Vec3(b, sign + d.y * d.y * a, -d.y);
}

// The box's extent along axis e, relative to the origin o.
void extentAlong(const Box3& b, const Vec3& e, const Vec3& o, float& lo, float& hi) {
    lo = hi = -glm::dot(e, o);
    for (int k = 0; k < 3; ++k) {
        const float a = e[k] * b.lower[k], c = e[k] * b.upper[k];
        lo += std::min(a, c);
        hi += std::max(a, c);
    }
}

// Narrows [t0, t1] to where lo(t) <= 0 <= hi(t), both linear between their ends.
bool containsOrigin(float lo0, float lo1, float hi0, float hi1, float& t0, float& t1) {
    auto keep = [&](float g0, float g1) {  // g(t) <= 0
        if (g0 > 0 && g1 > 0) return false;
        if (g0 > 0) t0 = std::max(t0, g0 / (g0 - g1) - 1e-5f);
        if (g1 > 0) t1 = std::min(t1, g0 / (g0 - g1) + 1e-5f);
        return true;
    };
    return keep(lo0, lo1) && keep(-hi0, -hi1) && t0 <= t1;
}

// Squared distance between the ray's line and the segment [p, q].
float lineSegmentDistance2(const Vec3& o, const Vec3& d, const Vec3& p, const Vec3& q) {
    const Vec3 u = q - p, w = p - o;
    const float dd = glm::dot(d, d), du = glm::dot(d, u), uu = glm::dot(u, u);
    const float dw = glm::dot(d, w), uw = glm::dot(u, w);
    const float denom = dd * uu - du * du;
    float s = denom > 1e-20f ? std::clamp((du * dw - dd * uw) / denom, 0.0f, 1.0f) : 0.0f;
    const float t = (dw + s * du) / dd;  // nearest line point to the segment point at s
    const Vec3 gap = w + s * u - t * d;
    return glm::dot(gap, gap);
}

}  // namespace

bool hitsTFragmentAt(const Ray& ray, const TFragment& f, float t, float& lambda,
                     TFragmentWork& work) {
    const Vec3 c = lerp(f.position0, f.position1, t);
    ++work.sphereTests;
    const Vec3 oc = c - ray.origin;
    const float along = glm::dot(oc, ray.direction) / glm::dot(ray.direction, ray.direction);
    const Vec3 off = oc - along * ray.direction;
    if (glm::dot(off, off) > f.radius * f.radius) return false;
    ++work.cubeTests;
    const float half = f.radius * 0.57735027f;  // the cube inside the circumsphere
    return rayHitsBox(ray, {c - half, c + half}, ray.lambdaMin, ray.lambdaMax, lambda);
}

TFragmentBvh::TFragmentBvh(const std::vector<TFragment>& fragments, TFragmentWork& work)
    : fragments_(&fragments) {
    const std::size_t n = fragments.size();
    if (n == 0) return;
    Box3 scene;
    for (const TFragment& f : fragments) scene.extend(0.5f * (f.position0 + f.position1));
    const Vec3 extent = glm::max(scene.upper - scene.lower, Vec3(1e-20f));
    std::vector<std::uint64_t> keys(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 mid = 0.5f * (fragments[i].position0 + fragments[i].position1);
        keys[i] = (std::uint64_t(morton((mid - scene.lower) / extent)) << 32) | i;
    }
    std::sort(keys.begin(), keys.end());
    nodes_.assign(2 * n - 1, Node{});
    for (std::size_t j = 0; j < n; ++j) nodes_[n - 1 + j].fragment = std::uint32_t(keys[j]);
    // Karras 2012: internal node i's range and split from common-prefix lengths.
    const auto delta = [&](std::int64_t i, std::int64_t j) {
        if (j < 0 || j >= std::int64_t(n)) return -1;
        return std::countl_zero(keys[std::size_t(i)] ^ keys[std::size_t(j)]);
    };
    for (std::int64_t i = 0; i + 1 < std::int64_t(n); ++i) {
        const int d = delta(i, i + 1) - delta(i, i - 1) >= 0 ? 1 : -1;
        const int minPrefix = delta(i, i - d);
        std::int64_t lmax = 2;
        while (delta(i, i + lmax * d) > minPrefix) lmax *= 2;
        std::int64_t l = 0;
        for (std::int64_t t = lmax / 2; t >= 1; t /= 2)
            if (delta(i, i + (l + t) * d) > minPrefix) l += t;
        const std::int64_t j = i + l * d;
        const int nodePrefix = delta(i, j);
        std::int64_t s = 0;
        for (std::int64_t t = (l + 1) / 2;; t = (t + 1) / 2) {
            if (delta(i, i + (s + t) * d) > nodePrefix) s += t;
            if (t == 1) break;
        }
        const std::int64_t gamma = i + s * d + std::min(d, 0);
        Node& node = nodes_[std::size_t(i)];
        node.left = std::int32_t(std::min(i, j) == gamma ? std::int64_t(n) - 1 + gamma : gamma);
        node.right =
            std::int32_t(std::max(i, j) == gamma + 1 ? std::int64_t(n) - 1 + gamma + 1 : gamma + 1);
    }
    // Bounds, children before parents (post-order with an explicit stack).
    std::vector<std::pair<std::int32_t, bool>> stack{{0, false}};
    while (!stack.empty()) {
        auto [node, childrenDone] = stack.back();
        stack.pop_back();
        Node& nd = nodes_[std::size_t(node)];
        if (nd.left < 0) {  // a leaf: its capsule's end spheres
            const TFragment& f = fragments[nd.fragment];
            nd.bounds.bounds0 = {f.position0 - f.radius, f.position0 + f.radius};
            nd.bounds.bounds1 = {f.position1 - f.radius, f.position1 + f.radius};
            continue;
        }
        if (!childrenDone) {
            stack.push_back({node, true});
            stack.push_back({nd.left, false});
            stack.push_back({nd.right, false});
            continue;
        }
        nd.bounds = nodes_[std::size_t(nd.left)].bounds;
        nd.bounds.extend(nodes_[std::size_t(nd.right)].bounds);
    }
    work.bvhNodes += std::int64_t(nodes_.size());
}

void TFragmentBvh::collect(const Ray& ray, int limit, std::vector<std::uint32_t>& out,
                           TFragmentWork& work) const {
    out.clear();
    if (nodes_.empty()) return;
    const Vec3 d = glm::normalize(ray.direction);
    Vec3 e1, e2;
    basisAcross(d, e1, e2);
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[std::size_t(stack[--top])];
        ++work.rayNodeTests;
        float lo0, hi0, lo1, hi1, t0 = 0.0f, t1 = 1.0f;
        extentAlong(node.bounds.bounds0, e1, ray.origin, lo0, hi0);
        extentAlong(node.bounds.bounds1, e1, ray.origin, lo1, hi1);
        if (!containsOrigin(lo0, lo1, hi0, hi1, t0, t1)) continue;
        extentAlong(node.bounds.bounds0, e2, ray.origin, lo0, hi0);
        extentAlong(node.bounds.bounds1, e2, ray.origin, lo1, hi1);
        if (!containsOrigin(lo0, lo1, hi0, hi1, t0, t1)) continue;
        if (node.left >= 0) {
            if (top + 2 > 128) continue;  // deeper than any tree of 2^64 keys; never taken
            stack[top++] = node.right;
            stack[top++] = node.left;
            continue;
        }
        const TFragment& f = (*fragments_)[node.fragment];
        ++work.capsuleTests;
        if (lineSegmentDistance2(ray.origin, d, f.position0, f.position1) > f.radius * f.radius)
            continue;
        if (int(out.size()) >= limit) {
            ++work.collectOverflow;
            continue;
        }
        out.push_back(node.fragment);
    }
    work.collected += std::int64_t(out.size());
}

std::int64_t TFragmentBvh::nearestAt(const Ray& ray, float t, float& lambda,
                                     TFragmentWork& work) const {
    std::int64_t best = -1;
    lambda = ray.lambdaMax;
    if (nodes_.empty()) return best;
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    Ray r = ray;
    while (top > 0) {
        const Node& node = nodes_[std::size_t(stack[--top])];
        ++work.rayNodeTests;
        float entry;
        if (!rayHitsBox(r, node.bounds.at(t), r.lambdaMin, r.lambdaMax, entry)) continue;
        if (node.left >= 0) {
            if (top + 2 > 128) continue;
            stack[top++] = node.right;
            stack[top++] = node.left;
            continue;
        }
        float hit;
        if (hitsTFragmentAt(r, (*fragments_)[node.fragment], t, hit, work) && hit < lambda) {
            ++work.visibilitySamples;
            lambda = hit;
            r.lambdaMax = hit;
            best = node.fragment;
        }
    }
    return best;
}

}  // namespace patchsim
