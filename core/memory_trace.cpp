#include "core/memory_trace.h"

#include <bit>

namespace patchsim {

MemoryTrace::MemoryTrace(int width, int height, int tileSize, int samplesPerPixel)
    : width_(width),
      height_(height),
      tileSize_(tileSize),
      spp_(samplesPerPixel),
      tilesX_((width + tileSize - 1) / tileSize),
      tilesY_((height + tileSize - 1) / tileSize),
      words_((std::size_t(tileSize) * std::size_t(tileSize) * std::size_t(samplesPerPixel) + 63) /
             64),
      tiles_(std::size_t(tilesX_) * std::size_t(tilesY_)) {}

namespace {

std::uint64_t bitsSet(std::span<const std::uint64_t> mask) {
    std::uint64_t n = 0;
    for (std::uint64_t w : mask) n += std::uint64_t(std::popcount(w));
    return n;
}

}  // namespace

std::uint64_t MemoryTrace::samplesRead() const {
    std::uint64_t n = 0;
    for (const TileTrace& t : tiles_)
        for (const TracedPass& p : t.passes) n += bitsSet(readMask(t, p));
    return n;
}

std::uint64_t MemoryTrace::samplesWritten() const {
    std::uint64_t n = 0;
    for (const TileTrace& t : tiles_)
        for (const TracedPass& p : t.passes) n += bitsSet(writeMask(t, p));
    return n;
}

std::uint64_t MemoryTrace::bytes() const {
    std::uint64_t n = 0;
    for (const TileTrace& t : tiles_)
        n += t.passes.size() * sizeof(TracedPass) + t.masks.size() * sizeof(std::uint64_t);
    return n;
}

void TileTraceWriter::beginTile(int tileX, int tileY) {
    tile_ = &trace_->tile(std::size_t(tileY) * std::size_t(trace_->tilesX()) + std::size_t(tileX));
    tile_->passes.clear();
    tile_->masks.clear();
    x0_ = tileX * trace_->tileSize();
    y0_ = tileY * trace_->tileSize();
}

void TileTraceWriter::beginPass(std::uint32_t patch) {
    const auto offset = std::uint32_t(tile_->masks.size());
    tile_->passes.push_back({patch, offset});
    tile_->masks.resize(tile_->masks.size() + 2 * trace_->wordsPerMask(), 0);
    open_ = true;
}

void TileTraceWriter::set(std::size_t bufferIndex, std::size_t maskWord) {
    if (!open_) return;
    const auto spp = std::size_t(trace_->samplesPerPixel());
    const std::size_t pixel = bufferIndex / spp, sample = bufferIndex % spp;
    const auto width = std::size_t(trace_->width());
    const std::size_t x = pixel % width - std::size_t(x0_), y = pixel / width - std::size_t(y0_);
    const std::size_t bit = (y * std::size_t(trace_->tileSize()) + x) * spp + sample;
    tile_->masks[tile_->passes.back().maskOffset + maskWord + bit / 64] |= std::uint64_t(1)
                                                                           << (bit % 64);
}

void TileTraceWriter::endPass() {
    if (!open_) return;
    open_ = false;
    const TracedPass& pass = tile_->passes.back();
    if (bitsSet(trace_->readMask(*tile_, pass)) != 0) return;
    tile_->masks.resize(pass.maskOffset);
    tile_->passes.pop_back();
}

}  // namespace patchsim
