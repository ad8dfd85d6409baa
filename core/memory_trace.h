#pragma once
// What a frame's visibility step did to the per-sample surfaces, pass by pass, recorded by the
// rasterizer for the memory model (pipeline/timing/memory_model.h) to replay through the caches
// of any hardware configuration. Recorded only when the hardware models memory.
//
// Representation
// --------------
// The frame is cut into regions, each worked on by one worker from start to end: the patch
// method's screen tiles (row-major), or the bounding methods' bands of rows (top to bottom). A
// region keeps its passes in the order they ran: the patch method's groups on the tile in patch
// order, the bounding methods' triangles on the band in patch order. A pass names the patch its
// work is charged to and two lists of the region's samples: those whose depth it read for the z
// test, and those whose visibility it wrote (a nearer hit), each sorted and without repeats. A
// sample's number in its region is ((y - y0) * stride + (x - x0)) * spp + s, where (x0, y0) is
// the region's corner and `stride` its width in pixels. A region's lists lie in two pools, a pass
// naming where its runs begin; a run ends where the next pass's begins. A pass that read no
// sample is kept only in a trace of tiles: the patch method's tile test reads the group's
// hierarchy whether or not a sample is then tested (a spilled hierarchy's traffic).
//
// With transparency a pass also lists, in the order they were made, its offers of a transparent
// fragment to a sample's layers (rasterizer/common/transparent_layers.h): the sample's number,
// with kAppended set when the offer added a layer (else it replaced one, merged with one or was
// dropped). The replay follows each sample's layer count from these.
//
// The trace holds no addresses: the surface layout is the memory model's, so one trace serves
// every layout and cache size a hardware file or an `explore` grid describes. It takes 4 bytes
// per sample read or written by a pass and per offer, and 16 per pass. An image-space method
// adds its full-screen passes after the resolve (core/image_pass_trace.h).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/image_pass_trace.h"

namespace patchsim {

struct TracedPass {
    std::uint32_t patch = 0;       // the patch the pass's work is charged to
    std::uint32_t readBegin = 0;   // into RegionTrace::reads
    std::uint32_t writeBegin = 0;  // into RegionTrace::writes
    std::uint32_t offerBegin = 0;  // into RegionTrace::offers
};

// An offer's flag: it added a layer to the sample.
inline constexpr std::uint32_t kAppended = 1u << 31;

struct RegionTrace {
    int x0 = 0, y0 = 0, stride = 0;  // corner and width in pixels
    std::vector<TracedPass> passes;
    std::vector<std::uint32_t> reads, writes, offers;
};

class MemoryTrace {
  public:
    // Regions of `tileSize` x `tileSize` pixels, row-major.
    static MemoryTrace tiles(int width, int height, int tileSize, int samplesPerPixel);
    // `bands` bands of whole rows, band b the rows [b H / bands, (b + 1) H / bands).
    static MemoryTrace bands(int width, int height, int bands, int samplesPerPixel);

    int width() const { return width_; }
    int height() const { return height_; }
    int samplesPerPixel() const { return spp_; }
    // Layers a sample keeps with transparency (the render's --max-layers); 0: no transparency.
    int layerSlots() const { return layerSlots_; }
    void setLayerSlots(int slots) { layerSlots_ = slots; }
    // The passes are an accumulation buffer's (the interleaved method): the modelled hardware
    // renders a whole frame per sample index, so the memory model replays the passes once per
    // index, each time with that index's samples only (pipeline/timing/memory_model.h).
    bool accumulation() const { return accumulation_; }
    void setAccumulation(bool accumulation) { accumulation_ = accumulation; }
    // The method records opaque frames only (a transparent frame's trace is dropped): what it
    // does with the layers after the visibility step is not modelled.
    bool opaqueOnly() const { return opaqueOnly_ || accumulation_; }
    void setOpaqueOnly() { opaqueOnly_ = true; }
    // Frames rendered after this one onto surfaces of their own (reprojection's frame at
    // shutter close), each replayed with its resolve after this frame's; same regions, no
    // passes yet.
    MemoryTrace& addLaterFrame();
    const std::vector<MemoryTrace>& laterFrames() const { return laterFrames_; }
    // The frame was resolved (read back and its image written); a later frame a method renders
    // but does not resolve (reprojection's, on a still frame) is not.
    bool resolved() const { return resolved_; }
    void setResolved(bool resolved) { resolved_ = resolved; }
    // The image-space passes after the resolves (core/image_pass_trace.h), for a method that
    // runs them; null until started. Its first planes are this frame's resolved image and then
    // each later frame's.
    ImagePassTrace& startImagePasses() {
        return imagePasses_.emplace(width_, height_, int(1 + laterFrames_.size()));
    }
    const ImagePassTrace* imagePasses() const { return imagePasses_ ? &*imagePasses_ : nullptr; }

    std::size_t regionCount() const { return regions_.size(); }
    RegionTrace& region(std::size_t index) { return regions_[index]; }
    const RegionTrace& region(std::size_t index) const { return regions_[index]; }

    std::span<const std::uint32_t> reads(const RegionTrace& r, std::size_t pass) const;
    std::span<const std::uint32_t> writes(const RegionTrace& r, std::size_t pass) const;
    std::span<const std::uint32_t> offers(const RegionTrace& r, std::size_t pass) const;

    // Sums over every pass, for tests and reports.
    std::uint64_t samplesRead() const;
    std::uint64_t samplesWritten() const;
    std::uint64_t fragmentsOffered() const;
    std::uint64_t layersAppended() const;
    std::uint64_t bytes() const;  // what the trace holds

  private:
    MemoryTrace(int width, int height, int samplesPerPixel)
        : width_(width), height_(height), spp_(samplesPerPixel) {}
    void addRegion(int x0, int y0, int stride) {
        RegionTrace& r = regions_.emplace_back();
        r.x0 = x0;
        r.y0 = y0;
        r.stride = stride;
    }
    int width_, height_, spp_, layerSlots_ = 0;
    bool accumulation_ = false, opaqueOnly_ = false, resolved_ = true;
    std::vector<RegionTrace> regions_;
    std::vector<MemoryTrace> laterFrames_;
    std::optional<ImagePassTrace> imagePasses_;
};

// Records one region's passes (one worker per region, so no locking). The rasterizer names each
// sample by its visibility-buffer index (pixel-major: (y * width + x) * spp + s).
class RegionTraceWriter {
  public:
    explicit RegionTraceWriter(MemoryTrace& trace) : trace_(&trace) {}
    // Keep passes that read no sample (MemoryTrace::tiles).
    void keepEmptyPasses() { keepEmpty_ = true; }

    void beginRegion(std::size_t index);
    void beginPass(std::uint32_t patch);
    void read(std::size_t bufferIndex) { region_->reads.push_back(local(bufferIndex)); }
    void wrote(std::size_t bufferIndex) { region_->writes.push_back(local(bufferIndex)); }
    void offered(std::size_t bufferIndex, bool appended) {
        region_->offers.push_back(local(bufferIndex) | (appended ? kAppended : 0u));
    }
    // Sorts the pass's lists and drops repeats; keeps the pass if it read a sample (or always,
    // with keepEmptyPasses).
    void endPass();

  private:
    std::uint32_t local(std::size_t bufferIndex) const;

    MemoryTrace* trace_;
    RegionTrace* region_ = nullptr;
    bool keepEmpty_ = false;
};

}  // namespace patchsim
