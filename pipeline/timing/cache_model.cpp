#include "pipeline/timing/cache_model.h"

#include <algorithm>
#include <stdexcept>

namespace patchsim {

const char* replacementName(Replacement r) {
    return r == Replacement::Lru ? "lru" : "fifo";
}

void CacheStats::add(const CacheStats& o) {
    reads += o.reads;
    writes += o.writes;
    readHits += o.readHits;
    writeHits += o.writeHits;
    writebacks += o.writebacks;
}

CacheModel::CacheModel(const CacheGeometry& geometry)
    : geometry_(geometry),
      sets_(geometry.sets()),
      lines_(geometry.sets() * geometry.ways, kEmpty),
      dirty_(lines_.size(), 0) {
    // The hardware reader refuses such geometry; a cache built in code must not divide by zero.
    if (sets_ == 0) throw std::invalid_argument("a cache needs at least one set of lines");
}

CacheModel::Outcome CacheModel::access(std::uint64_t line, bool write) {
    const std::size_t ways = geometry_.ways;
    const std::size_t base = std::size_t(line % sets_) * ways;
    std::uint64_t* set = lines_.data() + base;
    std::uint8_t* dirty = dirty_.data() + base;
    (write ? stats_.writes : stats_.reads) += 1;
    const std::size_t at = std::size_t(std::find(set, set + ways, line) - set);
    Outcome outcome;
    std::size_t slot = at;
    if (at < ways) {
        outcome.hit = true;
        (write ? stats_.writeHits : stats_.readHits) += 1;
        if (geometry_.replacement == Replacement::Fifo) {
            dirty[at] |= std::uint8_t(write);
            return outcome;
        }
    } else {
        slot = ways - 1;  // the line to evict (or an empty slot: empty slots sit at the end)
        if (set[slot] != kEmpty && dirty[slot]) {
            outcome.writeback = set[slot];
            ++stats_.writebacks;
        }
        set[slot] = line;
        dirty[slot] = 0;
    }
    // To the front, in both cases: under LRU the most recent, under FIFO the newest fill.
    const std::uint8_t wasDirty = dirty[slot];
    std::copy_backward(set, set + slot, set + slot + 1);
    std::copy_backward(dirty, dirty + slot, dirty + slot + 1);
    set[0] = line;
    dirty[0] = std::uint8_t(wasDirty | std::uint8_t(write));
    return outcome;
}

void CacheModel::invalidate(std::uint64_t line) {
    const std::size_t ways = geometry_.ways;
    const std::size_t base = std::size_t(line % sets_) * ways;
    std::uint64_t* set = lines_.data() + base;
    std::uint8_t* dirty = dirty_.data() + base;
    const std::size_t at = std::size_t(std::find(set, set + ways, line) - set);
    if (at == ways) return;
    // The later slots move up one, keeping their order; the freed slot goes to the end, where
    // empty slots sit.
    std::copy(set + at + 1, set + ways, set + at);
    std::copy(dirty + at + 1, dirty + ways, dirty + at);
    set[ways - 1] = kEmpty;
    dirty[ways - 1] = 0;
}

}  // namespace patchsim
