#pragma once
// The t-fragment hierarchy (Widmer et al. 2016, section 3.3): an LBVH over the t-fragments'
// capsules, rebuilt every frame, and the two ways of tracing it.
//
// Representation
// --------------
// Leaves are t-fragments sorted by the 30-bit Morton code of their capsule's midpoint (ties by
// index, so every key is unique); the internal nodes' topology is Karras's (2012): internal node
// i covers a key range found from the common-prefix lengths of its neighbours, split where the
// prefix changes. Node i < n-1 is internal, node n-1+j is leaf j. Every node holds a t-AABB:
// boxes at t = 0 and t = 1 around its capsules' end spheres, blended linearly between.
//
// Decoupled tracing (the paper): a lens ray is tested against a node's t-AABB in ray space: with
// an orthonormal basis (e1, e2) across the ray, the box's extent along e1 and along e2 is linear
// in t, so each gives the times the ray's origin projects inside; the node is hit when the two
// intervals meet (conservative: the box's projection is replaced by its bounding rectangle).
// Leaves collect their t-fragment when the ray passes within the capsule. Time-sampled tracing
// (the comparison of the paper's section 4.3): one traversal per time sample, boxes blended to
// that time, leaves tested at once with the sphere then the cube.

#include <cstdint>
#include <vector>

#include "backend/tfragment/tfragment_generation.h"
#include "core/lbbox.h"
#include "core/ray.h"

namespace patchsim {

class TFragmentBvh {
  public:
    TFragmentBvh(const std::vector<TFragment>& fragments, TFragmentWork& work);

    // Indices of the t-fragments the ray may meet at some time (at most `limit`; the rest are
    // counted in work.collectOverflow).
    void collect(const Ray& ray, int limit, std::vector<std::uint32_t>& out,
                 TFragmentWork& work) const;
    // The nearest t-fragment the ray meets at time `t` (sphere, then cube); -1 when none. `lambda`
    // gets its ray parameter.
    std::int64_t nearestAt(const Ray& ray, float t, float& lambda, TFragmentWork& work) const;

  private:
    struct Node {
        LBBox bounds;
        std::int32_t left = -1, right = -1;  // children; leaves have none
        std::uint32_t fragment = 0;          // leaves: the t-fragment
    };
    const std::vector<TFragment>* fragments_;
    std::vector<Node> nodes_;
};

// The ray parameter at which the ray enters the t-fragment's cube at time t (pixel-sized, around
// its position then), after the circumsphere test; false when it misses either.
bool hitsTFragmentAt(const Ray& ray, const TFragment& f, float t, float& lambda,
                     TFragmentWork& work);

}  // namespace patchsim
