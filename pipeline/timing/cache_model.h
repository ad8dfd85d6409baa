#pragma once
// One cache of the modelled memory system, simulated line by line from an address stream, so
// its hit rate is measured rather than assumed.
//
// Representation
// --------------
// `sets` x `ways` slots. Each slot holds a line number (byte address / line size; kEmpty when
// unused) and a dirty bit. A line lives in set (line mod sets). Within a set the slots are kept
// in replacement order, slot 0 the next to stay longest: under LRU a hit moves its line to slot
// 0, under FIFO only a fill does; a fill into a full set evicts the last slot. Write-back and
// write-allocate: a write marks its line dirty, and an evicted dirty line is returned to the
// caller to write below. Whether a miss must fetch its line is the caller's business (a write
// that covers the whole line, or a line still in its cleared state, fetches nothing).

#include <cstdint>
#include <string>
#include <vector>

namespace patchsim {

enum class Replacement : std::uint8_t { Lru, Fifo };
const char* replacementName(Replacement r);

struct CacheGeometry {
    std::uint64_t sizeBytes = 16 * 1024;
    std::uint32_t lineBytes = 64;
    std::uint32_t ways = 4;
    Replacement replacement = Replacement::Lru;

    std::uint64_t lines() const { return sizeBytes / lineBytes; }
    std::uint64_t sets() const { return lines() / ways; }
};

struct CacheStats {
    std::uint64_t reads = 0, writes = 0;  // line accesses
    std::uint64_t readHits = 0, writeHits = 0;
    std::uint64_t writebacks = 0;  // dirty lines evicted or flushed

    std::uint64_t accesses() const { return reads + writes; }
    std::uint64_t hits() const { return readHits + writeHits; }
    std::uint64_t misses() const { return accesses() - hits(); }
    double hitRate() const { return accesses() ? double(hits()) / double(accesses()) : 0.0; }
    void add(const CacheStats& o);
};

class CacheModel {
  public:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);

    explicit CacheModel(const CacheGeometry& geometry);

    struct Outcome {
        bool hit = false;
        std::uint64_t writeback = kEmpty;  // a dirty line evicted to make room
    };
    // One access to `line`; a miss fills it.
    Outcome access(std::uint64_t line, bool write);
    // Drops `line` if held, dirty or not, without writing it back (a fast clear of dead data).
    void invalidate(std::uint64_t line);
    // Writes back every dirty line (`emit(line)` for each) and keeps them, clean.
    template <class Emit>
    void flush(Emit emit) {
        for (std::size_t s = 0; s < lines_.size(); ++s)
            if (lines_[s] != kEmpty && dirty_[s]) {
                emit(lines_[s]);
                dirty_[s] = 0;
                ++stats_.writebacks;
            }
    }

    const CacheStats& stats() const { return stats_; }
    const CacheGeometry& geometry() const { return geometry_; }

  private:
    CacheGeometry geometry_;
    std::uint64_t sets_;
    std::vector<std::uint64_t> lines_;  // sets x ways, each set in replacement order
    std::vector<std::uint8_t> dirty_;
    CacheStats stats_;
};

}  // namespace patchsim
