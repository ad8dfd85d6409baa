#include "rasterizer/patent/hierarchy_orders.h"

#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "core/parallel.h"

namespace patchsim {

namespace {

// A 64-bit mix of a byte range, eight bytes at a time (the tail zero-padded).
std::uint64_t mixBytes(const void* data, std::size_t bytes, std::uint64_t h) {
    const auto* p = static_cast<const unsigned char*>(data);
    auto mix = [&h](std::uint64_t word) {
        h ^= word + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdull;
    };
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
        std::uint64_t word;
        std::memcpy(&word, p + i, 8);
        mix(word);
    }
    std::uint64_t tail = 0;
    if (i < bytes) std::memcpy(&tail, p + i, bytes - i);  // an empty mesh's data may be null
    mix(tail ^ bytes);
    return h;
}

std::uint64_t patternHash(const MovingMesh& m) {
    const std::uint64_t h = mixBytes(m.domain.data(), m.domain.size() * sizeof(Vec2), 0);
    return mixBytes(m.indices.data(), m.indices.size() * sizeof(std::uint32_t), h);
}

// Whether two arrays hold the same bytes (memcmp is not defined on the null data of an empty one).
template <typename T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

bool sameTessellationPattern(const MovingMesh& a, const MovingMesh& b) {
    return sameBytes(a.domain, b.domain) && sameBytes(a.indices, b.indices);
}

HierarchyOrders::HierarchyOrders(const std::vector<const MovingMesh*>& meshes, int maxPerGroup,
                                 int leafSize, int threads)
    : source_(meshes.size()), orders_(meshes.size()) {
    std::vector<std::uint64_t> hashes(meshes.size());
    parallelFor(meshes.size(), threads,
                [&](int, std::size_t u) { hashes[u] = patternHash(*meshes[u]); });
    // The first unit of each hash is its candidate source.
    std::unordered_map<std::uint64_t, std::size_t> firstOfHash;
    for (std::size_t u = 0; u < meshes.size(); ++u)
        source_[u] = firstOfHash.try_emplace(hashes[u], u).first->second;
    parallelFor(meshes.size(), threads, [&](int, std::size_t u) {
        if (source_[u] != u && sameTessellationPattern(*meshes[u], *meshes[source_[u]])) return;
        source_[u] = u;
        orders_[u] = hierarchyOrder(*meshes[u], maxPerGroup, leafSize);
    });
}

std::size_t HierarchyOrders::ordersMade() const {
    std::size_t made = 0;
    for (std::size_t u = 0; u < source_.size(); ++u) made += source_[u] == u;
    return made;
}

}  // namespace patchsim
