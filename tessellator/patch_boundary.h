#pragma once
// Points on a patch's boundary, and making two patches agree on the points of an edge they share.
//
// Representation
// --------------
// A domain point on a patch edge is named by its edge and its parameter s from the edge's start
// corner, in units of 2^-17 (`kEdgeOne`). The D3D11 tessellator places points on multiples of
// 2^-16; half of a cage edge (the sub-patches of an N-gon) seen from the whole edge needs one bit
// more, so every name here is exact.
//
// Why points are inserted
// -----------------------
// Two patches that share a whole cage edge get the same factor and, from the D3D11 tessellator,
// the same points. An N-gon's sub-patches see the edge as two halves at half the factor; under
// integer partitioning the hull shader makes the whole factor even so the points coincide, but a
// fractional pattern at factor F is not two patterns at F/2 (and fractional_odd has no point at
// the middle, where the sub-patches have a corner). There the tessellator's output alone leaves
// T-junctions. `insertEdgePoints` gives each side the other side's points: the boundary triangle
// that spans a missing point is split into a fan from its opposite vertex, keeping its winding.
// Both sides then hold the union of the two patterns, bit for bit, and the mesh is watertight.

#include <cstdint>
#include <vector>

#include "tessellator/d3d11_tessellator.h"
#include "tessellator/subdivision_mesh.h"

namespace patchsim {

inline constexpr std::uint32_t kEdgeOne = 1u << 17;

// Where a domain point lies on its patch's boundary: a corner, or an edge and its parameter.
struct BoundaryPlace {
    int corner = -1;
    int edge = -1;
    std::uint32_t s = 0;  // units of 2^-17 from the edge's start corner
};
BoundaryPlace locateOnBoundary(PatchDomain domain, float u, float v);

// The local (u,v) of the point at parameter s (units of 2^-17) on a patch edge.
DomainPoint edgePoint(PatchDomain domain, int edge, std::uint32_t s);

// Parameters of the tessellation's points on `edge`, corners included, in increasing order.
std::vector<std::uint32_t> pointsOnEdge(const Tessellation& tessellation, PatchDomain domain,
                                        int edge);

// Adds the points at parameters `wanted` (those the edge does not already have, strictly between
// its corners) to `edge`, splitting the boundary triangles that span them. Returns how many were
// added.
int insertEdgePoints(Tessellation& tessellation, PatchDomain domain, int edge,
                     const std::vector<std::uint32_t>& wanted);

}  // namespace patchsim
