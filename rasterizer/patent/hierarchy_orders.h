#pragma once
// The order each rasterization unit's hierarchies are built from, made once per tessellation
// pattern in a frame. Ordering a mesh's triangles (median splits of their domain centroids, to
// groups and then to leaves) depends only on the domain positions and index triples the
// tessellator gave it, not on where the patch is: every patch of one domain (quad or triangle)
// tessellated with the same factors has the same order, which hardware could keep in a table per
// pattern. At one fixed factor a frame orders one mesh per domain; with adaptive factors, one per
// distinct set of edge and inside factors.
//
// Representation
// --------------
// Per unit: the unit whose order it uses (itself, or the first unit of the same pattern), and,
// for those that are their own source, the order. Units are matched by a hash of their domain
// and index bytes and then compared byte for byte, so a hash collision costs an order of its
// own, never a wrong one. Which unit is a pattern's source depends only on the units' order,
// not on the threads, so the orders (and the hierarchies) are the same on any thread count.

#include <cstddef>
#include <vector>

#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/patent/patch_hierarchy.h"

namespace patchsim {

class HierarchyOrders {
  public:
    HierarchyOrders(const std::vector<const MovingMesh*>& meshes, int maxPerGroup, int leafSize,
                    int threads);
    const HierarchyOrder& of(std::size_t unit) const { return orders_[source_[unit]]; }
    // How many orders were made (distinct patterns, plus hash collisions).
    std::size_t ordersMade() const;

  private:
    std::vector<std::size_t> source_;     // per unit
    std::vector<HierarchyOrder> orders_;  // per unit; filled where the unit is its own source
};

// Whether two meshes have the same domain positions and index triples, byte for byte.
bool sameTessellationPattern(const MovingMesh& a, const MovingMesh& b);

}  // namespace patchsim
