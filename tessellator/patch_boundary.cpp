#include "tessellator/patch_boundary.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace patchsim {

namespace {

std::uint32_t toEdgeUnits(float x) {
    return std::uint32_t(std::lround(double(x) * double(kEdgeOne)));
}

}  // namespace

BoundaryPlace locateOnBoundary(PatchDomain domain, float u, float v) {
    const std::uint32_t fu = toEdgeUnits(u), fv = toEdgeUnits(v);
    BoundaryPlace b;
    if (domain == PatchDomain::Quad) {
        if (fu == 0 && fv == 0)
            b.corner = 0;
        else if (fu == kEdgeOne && fv == 0)
            b.corner = 1;
        else if (fu == kEdgeOne && fv == kEdgeOne)
            b.corner = 2;
        else if (fu == 0 && fv == kEdgeOne)
            b.corner = 3;
        else if (fv == 0)
            b = {-1, 0, fu};
        else if (fu == kEdgeOne)
            b = {-1, 1, fv};
        else if (fv == kEdgeOne)
            b = {-1, 2, kEdgeOne - fu};
        else if (fu == 0)
            b = {-1, 3, kEdgeOne - fv};
        return b;
    }
    if (fu == 0 && fv == 0)
        b.corner = 0;
    else if (fu == kEdgeOne && fv == 0)
        b.corner = 1;
    else if (fu == 0 && fv == kEdgeOne)
        b.corner = 2;
    else if (fv == 0)
        b = {-1, 0, fu};
    else if (fu + fv == kEdgeOne)
        b = {-1, 1, fv};
    else if (fu == 0)
        b = {-1, 2, kEdgeOne - fv};
    return b;
}

DomainPoint edgePoint(PatchDomain domain, int edge, std::uint32_t s) {
    float uv[2];
    patchEdgePoint(domain, edge, float(s) / float(kEdgeOne), uv);
    return {uv[0], uv[1]};
}

namespace {

// (parameter, point index) of every point on `edge`, corners included, by parameter.
std::vector<std::pair<std::uint32_t, std::uint32_t>> indexedPointsOnEdge(const Tessellation& t,
                                                                         PatchDomain domain,
                                                                         int edge) {
    const int corners = domain == PatchDomain::Quad ? 4 : 3;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    for (std::uint32_t i = 0; i < t.points.size(); ++i) {
        const BoundaryPlace b = locateOnBoundary(domain, t.points[i].u, t.points[i].v);
        if (b.edge == edge)
            out.push_back({b.s, i});
        else if (b.corner == edge)
            out.push_back({0, i});
        else if (b.corner == (edge + 1) % corners)
            out.push_back({kEdgeOne, i});
    }
    std::sort(out.begin(), out.end());
    return out;
}

// Replaces the triangle with the directed or reversed edge a-b by a fan through `chain` (from a
// to b, both ends included) around its third vertex.
void splitBoundaryTriangle(Tessellation& t, std::uint32_t a, std::uint32_t b,
                           const std::vector<std::uint32_t>& chain) {
    std::vector<std::uint32_t>& idx = t.indices;
    for (std::size_t tri = 0; tri + 2 < idx.size(); tri += 3) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t from = idx[tri + std::size_t(k)];
            const std::uint32_t to = idx[tri + std::size_t((k + 1) % 3)];
            if (!((from == a && to == b) || (from == b && to == a))) continue;
            const std::uint32_t apex = idx[tri + std::size_t((k + 2) % 3)];
            // Walk the chain in the triangle's own direction so every piece keeps its winding.
            std::vector<std::uint32_t> path = chain;
            if (from == b) std::reverse(path.begin(), path.end());
            std::vector<std::uint32_t> fan;
            for (std::size_t j = 0; j + 1 < path.size(); ++j)
                fan.insert(fan.end(), {path[j], path[j + 1], apex});
            std::copy(fan.begin(), fan.begin() + 3, idx.begin() + std::ptrdiff_t(tri));
            idx.insert(idx.end(), fan.begin() + 3, fan.end());
            return;
        }
    }
    throw std::logic_error("no boundary triangle on a tessellated edge segment");
}

}  // namespace

std::vector<std::uint32_t> pointsOnEdge(const Tessellation& tessellation, PatchDomain domain,
                                        int edge) {
    std::vector<std::uint32_t> out;
    for (const auto& [s, index] : indexedPointsOnEdge(tessellation, domain, edge)) out.push_back(s);
    return out;
}

int insertEdgePoints(Tessellation& t, PatchDomain domain, int edge,
                     const std::vector<std::uint32_t>& wanted) {
    const auto existing = indexedPointsOnEdge(t, domain, edge);
    int added = 0;
    for (std::size_t seg = 0; seg + 1 < existing.size(); ++seg) {
        const auto [s0, a] = existing[seg];
        const auto [s1, b] = existing[seg + 1];
        std::vector<std::uint32_t> chain{a};
        for (const std::uint32_t s : wanted) {
            if (s <= s0 || s >= s1) continue;
            chain.push_back(std::uint32_t(t.points.size()));
            t.points.push_back(edgePoint(domain, edge, s));
        }
        if (chain.size() == 1) continue;
        chain.push_back(b);
        added += int(chain.size()) - 2;
        splitBoundaryTriangle(t, a, b, chain);
    }
    return added;
}

}  // namespace patchsim
