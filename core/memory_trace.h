#pragma once
// What a frame's visibility step did to the per-sample surfaces, pass by pass, recorded by the
// rasterizer for the memory model (pipeline/timing/memory_model.h) to replay through the caches
// of any hardware configuration. Recorded only when the hardware models memory.
//
// Representation
// --------------
// Per screen tile (row-major, tiles of `tileSize` pixels), the passes that touched it in the
// order they ran: the tile's groups in patch order. A pass is one group on one tile. It names
// the patch its work is charged to and two bit masks over the tile's samples: the samples whose
// depth it read for the z test, and the samples whose visibility it wrote (a nearer hit). A
// sample's bit is (pixel in tile) x spp + sample index, pixels row-major in the tile with a
// stride of `tileSize` (an edge tile's missing pixels are zero bits). A tile's masks lie in one
// pool, `wordsPerMask()` 64-bit words each, a pass's read mask at `maskOffset` and its write
// mask right after. A pass that read no sample is not kept.
//
// The trace holds no addresses: the surface layout is the memory model's, so one trace serves
// every layout and cache size a hardware file or an `explore` grid describes. Its size is two
// masks per (group, tile) pass that z-tested a sample: 256 bytes for 8x8 tiles at 16 spp.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace patchsim {

struct TracedPass {
    std::uint32_t patch = 0;       // the patch the pass's work is charged to
    std::uint32_t maskOffset = 0;  // into TileTrace::masks: the read mask, then the write mask
};

struct TileTrace {
    std::vector<TracedPass> passes;
    std::vector<std::uint64_t> masks;
};

class MemoryTrace {
  public:
    MemoryTrace(int width, int height, int tileSize, int samplesPerPixel);

    int width() const { return width_; }
    int height() const { return height_; }
    int tileSize() const { return tileSize_; }
    int samplesPerPixel() const { return spp_; }
    int tilesX() const { return tilesX_; }
    int tilesY() const { return tilesY_; }
    std::size_t wordsPerMask() const { return words_; }

    TileTrace& tile(std::size_t index) { return tiles_[index]; }
    const TileTrace& tile(std::size_t index) const { return tiles_[index]; }
    std::size_t tileCount() const { return tiles_.size(); }

    std::span<const std::uint64_t> readMask(const TileTrace& t, const TracedPass& p) const {
        return {t.masks.data() + p.maskOffset, words_};
    }
    std::span<const std::uint64_t> writeMask(const TileTrace& t, const TracedPass& p) const {
        return {t.masks.data() + p.maskOffset + words_, words_};
    }

    // Sums over every pass, for tests and reports.
    std::uint64_t samplesRead() const;
    std::uint64_t samplesWritten() const;
    std::uint64_t bytes() const;  // what the trace holds

  private:
    int width_, height_, tileSize_, spp_, tilesX_, tilesY_;
    std::size_t words_;
    std::vector<TileTrace> tiles_;
};

// Records one tile's passes into its TileTrace (one worker per tile, so no locking). The
// rasterizer names each sample by its visibility-buffer index.
class TileTraceWriter {
  public:
    explicit TileTraceWriter(MemoryTrace& trace) : trace_(&trace) {}

    void beginTile(int tileX, int tileY);
    void beginPass(std::uint32_t patch);
    void read(std::size_t bufferIndex) { set(bufferIndex, 0); }
    void wrote(std::size_t bufferIndex) { set(bufferIndex, trace_->wordsPerMask()); }
    // Keeps the pass if it read a sample.
    void endPass();

  private:
    void set(std::size_t bufferIndex, std::size_t maskWord);

    MemoryTrace* trace_;
    TileTrace* tile_ = nullptr;
    int x0_ = 0, y0_ = 0;
    bool open_ = false;
};

}  // namespace patchsim
