#include "core/memory_trace.h"

#include <algorithm>

namespace patchsim {

MemoryTrace MemoryTrace::tiles(int width, int height, int tileSize, int samplesPerPixel) {
    MemoryTrace trace(width, height, samplesPerPixel);
    for (int y = 0; y < height; y += tileSize)
        for (int x = 0; x < width; x += tileSize) trace.addRegion(x, y, tileSize);
    return trace;
}

MemoryTrace MemoryTrace::bands(int width, int height, int bands, int samplesPerPixel) {
    MemoryTrace trace(width, height, samplesPerPixel);
    for (int b = 0; b < bands; ++b) trace.addRegion(0, b * height / bands, width);
    return trace;
}

MemoryTrace& MemoryTrace::addLaterFrame() {
    MemoryTrace later(width_, height_, spp_);
    for (const RegionTrace& r : regions_) later.addRegion(r.x0, r.y0, r.stride);
    later.layerSlots_ = layerSlots_;
    return laterFrames_.emplace_back(std::move(later));
}

std::span<const std::uint32_t> MemoryTrace::reads(const RegionTrace& r, std::size_t pass) const {
    const std::size_t end =
        pass + 1 < r.passes.size() ? r.passes[pass + 1].readBegin : r.reads.size();
    return {r.reads.data() + r.passes[pass].readBegin, end - r.passes[pass].readBegin};
}

std::span<const std::uint32_t> MemoryTrace::writes(const RegionTrace& r, std::size_t pass) const {
    const std::size_t end =
        pass + 1 < r.passes.size() ? r.passes[pass + 1].writeBegin : r.writes.size();
    return {r.writes.data() + r.passes[pass].writeBegin, end - r.passes[pass].writeBegin};
}

std::span<const std::uint32_t> MemoryTrace::offers(const RegionTrace& r, std::size_t pass) const {
    const std::size_t end =
        pass + 1 < r.passes.size() ? r.passes[pass + 1].offerBegin : r.offers.size();
    return {r.offers.data() + r.passes[pass].offerBegin, end - r.passes[pass].offerBegin};
}

std::uint64_t MemoryTrace::samplesRead() const {
    std::uint64_t n = 0;
    for (const RegionTrace& r : regions_) n += r.reads.size();
    return n;
}

std::uint64_t MemoryTrace::samplesWritten() const {
    std::uint64_t n = 0;
    for (const RegionTrace& r : regions_) n += r.writes.size();
    return n;
}

std::uint64_t MemoryTrace::fragmentsOffered() const {
    std::uint64_t n = 0;
    for (const RegionTrace& r : regions_) n += r.offers.size();
    return n;
}

std::uint64_t MemoryTrace::layersAppended() const {
    std::uint64_t n = 0;
    for (const RegionTrace& r : regions_)
        n += std::uint64_t(std::count_if(r.offers.begin(), r.offers.end(),
                                         [](std::uint32_t o) { return (o & kAppended) != 0; }));
    return n;
}

std::uint64_t MemoryTrace::bytes() const {
    std::uint64_t n = 0;
    for (const RegionTrace& r : regions_)
        n += r.passes.size() * sizeof(TracedPass) +
             (r.reads.size() + r.writes.size() + r.offers.size()) * sizeof(std::uint32_t);
    if (imagePasses_) n += imagePasses_->bytes();
    for (const MemoryTrace& later : laterFrames_) n += later.bytes();
    return n;
}

void RegionTraceWriter::beginRegion(std::size_t index) {
    region_ = &trace_->region(index);
    region_->passes.clear();
    region_->reads.clear();
    region_->writes.clear();
    region_->offers.clear();
}

void RegionTraceWriter::beginPass(std::uint32_t patch) {
    region_->passes.push_back({patch, std::uint32_t(region_->reads.size()),
                               std::uint32_t(region_->writes.size()),
                               std::uint32_t(region_->offers.size())});
}

void RegionTraceWriter::endPass() {
    const TracedPass pass = region_->passes.back();
    const auto sortUnique = [](std::vector<std::uint32_t>& pool, std::uint32_t begin) {
        const auto first = pool.begin() + std::ptrdiff_t(begin);
        std::sort(first, pool.end());
        pool.erase(std::unique(first, pool.end()), pool.end());
    };
    sortUnique(region_->reads, pass.readBegin);
    sortUnique(region_->writes, pass.writeBegin);
    if (keepEmpty_ || region_->reads.size() > pass.readBegin) return;
    region_->writes.resize(pass.writeBegin);
    region_->offers.resize(pass.offerBegin);
    region_->passes.pop_back();
}

std::uint32_t RegionTraceWriter::local(std::size_t bufferIndex) const {
    const auto spp = std::size_t(trace_->samplesPerPixel());
    const std::size_t pixel = bufferIndex / spp, sample = bufferIndex % spp;
    const auto width = std::size_t(trace_->width());
    const std::size_t x = pixel % width - std::size_t(region_->x0);
    const std::size_t y = pixel / width - std::size_t(region_->y0);
    return std::uint32_t((y * std::size_t(region_->stride) + x) * spp + sample);
}

}  // namespace patchsim
