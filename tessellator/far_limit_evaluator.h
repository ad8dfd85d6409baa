#pragma once
// Limit stencils from Far's feature-adaptive patch table, for the cage faces that Debian's
// OpenSubdiv 3.5.0 cannot give to Bfr.
//
// Why it exists
// -------------
// OpenSubdiv 3.5.0's Bfr::IrregularPatchBuilder::sharpenBoundaryControlEdges overwrites the sharp
// edges it was given instead of appending the boundary ones (fixed upstream in 3.5.1). It runs for
// a face with an interior valence-2 vertex among its corners, a boundary vertex and a sharp edge
// nearby, and then hands uninitialised edge indices to Far, which reads out of bounds and may
// crash (OpenSubdiv's regression shape catmark_val2_interior). Debian 12 ships 3.5.0, so patchsim
// routes such faces here instead: `bfrBuilderIsUnsafe` names them.
//
// Representation
// --------------
// A second Far::TopologyRefiner over the same cage, refined adaptively around the affected faces
// to the depth Bfr uses for sharp features, a patch table with Gregory end caps, and one stencil
// table that expresses every refined vertex and end-cap point in the cage's own vertices. A limit
// stencil at a face-level (u,v) is the patch basis at that point pushed through those stencils, so
// it is a weight per cage vertex, exactly the form Bfr's EvaluateStencil gives. Const after
// construction, so any number of threads may evaluate at once.

#include <opensubdiv/far/topologyDescriptor.h>

#include <memory>
#include <vector>

#include "tessellator/limit_stencil.h"

namespace patchsim {

namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

// True when Bfr 3.5.0's irregular patch builder would read uninitialised sharp edges for `face`:
// a manifold interior corner vertex of valence 2, a boundary or non-manifold corner, and a sharp
// edge around a corner. Deliberately no narrower than that (checked under valgrind on every shape
// of OpenSubdiv 3.5.1's regression suite: every face it does not name builds cleanly).
bool bfrBuilderIsUnsafe(const osd::Far::TopologyLevel& level, int face);

class FarLimitEvaluator {
  public:
    // `faces` are the base faces to be evaluated; the refiner is built from `descriptor` the same
    // way as the mesh's own.
    FarLimitEvaluator(
        const osd::Far::TopologyDescriptor& descriptor,
        const osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>::Options& options,
        const std::vector<int>& faces);
    ~FarLimitEvaluator();
    FarLimitEvaluator(const FarLimitEvaluator&) = delete;
    FarLimitEvaluator& operator=(const FarLimitEvaluator&) = delete;

    // False for a hole or a face without a limit surface.
    bool hasSurface(int face) const;
    // Limit stencil of `face` at face-level (u,v) (Bfr's parameterization of the face).
    void evaluate(int face, const float faceUV[2], LimitStencil& out) const;
    // Cage vertices the face's surface depends on (empty for a face without a surface).
    const std::vector<int>& controlPoints(int face) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace patchsim
