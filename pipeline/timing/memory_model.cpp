#include "pipeline/timing/memory_model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <span>

namespace patchsim {

namespace {

struct MemoryClassInfo {
    const char* name;
    const char* definition;
};
constexpr MemoryClassInfo kClassInfo[] = {
#define PATCHSIM_MEMORY_CLASS_INFO(name, key, definition) {key, definition},
    PATCHSIM_MEMORY_CLASSES(PATCHSIM_MEMORY_CLASS_INFO)
#undef PATCHSIM_MEMORY_CLASS_INFO
};
static_assert(std::size(kClassInfo) == kMemoryClasses);

constexpr std::uint64_t kSurfaceAlignment = 4096;

std::uint64_t alignUp(std::uint64_t v) {
    return (v + kSurfaceAlignment - 1) / kSurfaceAlignment * kSurfaceAlignment;
}

// The caches, DRAM and what they count, accessed a line at a time.
class MemorySystem {
  public:
    // `depthScale`: per depth block (of `depthBlockBytes`, from address 0), its compressed size
    // over its uncompressed one (empty: uncompressed).
    static_assert(kCacheClients == 6, "a CacheModel per client below");
    MemorySystem(const MemoryConfig& config, std::uint64_t endAddress, std::size_t patchCount,
                 const std::vector<double>& depthScale, std::uint64_t depthBlockBytes)
        : depthScale_(depthScale),
          depthBlockBytes_(depthBlockBytes),
          line_(config.lineBytes()),
          caches_{CacheModel(config.caches[0].geometry), CacheModel(config.caches[1].geometry),
                  CacheModel(config.caches[2].geometry), CacheModel(config.caches[3].geometry),
                  CacheModel(config.caches[4].geometry), CacheModel(config.caches[5].geometry)},
          inDram_((endAddress / line_ + 64) / 64, 0),
          banks_(config.dramBanks, config.dramBytesPerClock,
                 config.dramBanks.modelled() ? patchCount : 0) {
        report_.patches.resize(patchCount);
    }

    std::uint64_t lineOf(std::uint64_t address) const { return address / line_; }

    // A client cache's access to `line`; consecutive accesses to one line are one access.
    void access(CacheClient client, std::uint64_t line, bool write, std::size_t patch) {
        std::uint64_t& last = last_[std::size_t(client)][write];
        if (line == last) return;
        last = line;
        ++report_.patches[patch].lineAccesses[std::size_t(client)];
        const CacheModel::Outcome out = caches_[std::size_t(client)].access(line, write);
        if (out.writeback != CacheModel::kEmpty) lastLevel(out.writeback, true, patch);
        // A miss fills the line from below, a write's too (it may cover part of the line).
        if (!out.hit) lastLevel(line, false, patch);
    }
    // A pass's accesses are coalesced among themselves, not with another pass's.
    void newPass() {
        last_ = kNoLast;
        lastStream_ = kNone;
    }
    // A write that covers whole lines (the image, written in order) goes to the LLC directly.
    void streamWrite(std::uint64_t line, std::size_t patch) {
        if (line == lastStream_) return;
        lastStream_ = line;
        lastLevel(line, true, patch);
    }
    // A read that bypasses the client caches (a hierarchy's spilled nodes).
    void readLastLevel(std::uint64_t line, std::size_t patch) { lastLevel(line, false, patch); }
    // Lines that hold data in DRAM before the frame (the scene's buffers).
    void markInDram(std::uint64_t firstLine, std::uint64_t lastLine) {
        for (std::uint64_t line = firstLine; line <= lastLine; ++line)
            inDram_[line / 64] |= std::uint64_t(1) << (line % 64);
    }
    void request(MemoryClass c, std::uint64_t bytes) {
        report_.requestedBytes[std::size_t(c)] += bytes;
    }
    // A fast clear of lines [first, last]: dropped from every cache unwritten, and cleared in
    // DRAM (a later read fetches nothing).
    void discard(std::uint64_t first, std::uint64_t last) {
        for (std::uint64_t line = first; line <= last; ++line) {
            for (CacheModel& cache : caches_) cache.invalidate(line);
            inDram_[line / 64] &= ~(std::uint64_t(1) << (line % 64));
        }
        newPass();
    }
    // Every dirty line written back, the client caches' through the LLC.
    void writeBack(std::size_t patch) {
        for (int c = 0; c < kCacheClients - 1; ++c)
            caches_[std::size_t(c)].flush(
                [&](std::uint64_t line) { lastLevel(line, true, patch); });
        caches_[kCacheClients - 1].flush([&](std::uint64_t line) { dramWrite(line, patch); });
        newPass();
    }
    MemoryReport finish() {
        for (int c = 0; c < kCacheClients; ++c)
            report_.caches[std::size_t(c)] = caches_[std::size_t(c)].stats();
        if (banksModelled()) {
            report_.dramBanks = banks_.stats();
            const std::vector<DramBanks::Time> times = banks_.patchTimes();
            for (std::size_t p = 0; p < report_.patches.size(); ++p) {
                report_.patches[p].dramCycles = times[p].cycles;
                report_.dramBanks.cyclesLimitedBy[std::size_t(times[p].limit)] += times[p].cycles;
            }
        }
        return std::move(report_);
    }

  private:
    static constexpr std::uint64_t kNone = CacheModel::kEmpty;

    void lastLevel(std::uint64_t line, bool write, std::size_t patch) {
        ++report_.patches[patch].lineAccesses[std::size_t(CacheClient::LastLevel)];
        const CacheModel::Outcome out =
            caches_[std::size_t(CacheClient::LastLevel)].access(line, write);
        if (out.writeback != CacheModel::kEmpty) dramWrite(out.writeback, patch);
        // A write brings a whole line (a write-back from above, or a streamed line); a read
        // miss fetches from DRAM, unless the line was never written there (still cleared).
        if (!out.hit && !write && holds(line)) {
            const std::uint64_t bytes = dramBytesOf(line);
            report_.dramReadBytes += bytes;
            ++report_.dramReads;
            ++report_.patches[patch].dramReads;
            dramTransfer(line, bytes, patch);
        }
    }
    void dramWrite(std::uint64_t line, std::size_t patch) {
        inDram_[line / 64] |= std::uint64_t(1) << (line % 64);
        const std::uint64_t bytes = dramBytesOf(line);
        report_.dramWriteBytes += bytes;
        dramTransfer(line, bytes, patch);
    }
    void dramTransfer(std::uint64_t line, std::uint64_t bytes, std::size_t patch) {
        report_.patches[patch].dramBytes += bytes;
        if (banksModelled()) banks_.access(line * line_, bytes, patch);
    }
    bool banksModelled() const { return banks_.modelled(); }
    // A line's bytes on the DRAM bus: a depth line at its block's compressed size.
    std::uint64_t dramBytesOf(std::uint64_t line) const {
        const std::uint64_t block = line * line_ / depthBlockBytes_;
        if (block >= depthScale_.size()) return line_;
        return std::uint64_t(std::ceil(double(line_) * depthScale_[std::size_t(block)]));
    }
    bool holds(std::uint64_t line) const { return inDram_[line / 64] >> (line % 64) & 1u; }

    const std::vector<double>& depthScale_;
    std::uint64_t depthBlockBytes_;
    std::uint64_t line_;
    std::array<CacheModel, kCacheClients> caches_;
    std::vector<std::uint64_t> inDram_;  // per line: written to DRAM this frame (else cleared)
    DramBanks banks_;
    using LastLines = std::array<std::array<std::uint64_t, 2>, kCacheClients>;
    static constexpr LastLines kNoLast{{{kNone, kNone},
                                        {kNone, kNone},
                                        {kNone, kNone},
                                        {kNone, kNone},
                                        {kNone, kNone},
                                        {kNone, kNone}}};
    LastLines last_ = kNoLast;
    std::uint64_t lastStream_ = kNone;
    MemoryReport report_;
};

// The transparent layers (see the essay in memory_model.h): a header per sample, then blocks of
// `slots` layers given out as samples get their first layer.
class LayerBuffer {
  public:
    LayerBuffer(const MemoryTrace& trace, const SurfaceLayout& layout, std::uint64_t base)
        : layout_(layout),
          slots_(std::uint64_t(trace.layerSlots())),
          headerBase_(base),
          blockBase_(alignUp(base + (slots_ ? layout.samples() * kLayerHeaderBytes : 0))),
          // At most a block per offer (a valid trace: per append), so every address lies below.
          end_(alignUp(blockBase_ + trace.fragmentsOffered() * slots_ * kLayerBytes)) {
        if (slots_ == 0) return;
        count_.assign(layout.samples(), 0);
        block_.assign(layout.samples(), 0);
    }
    std::uint64_t endAddress() const { return end_; }

    // An offer to sample (x, y, s), from the trace.
    void offer(int x, int y, int s, bool appended, std::size_t patch, MemorySystem& memory) {
        if (slots_ == 0) return;  // offers are recorded only beside the trace's layer slots
        const std::uint64_t sample = layout_.sampleIndex(x, y, s);
        const std::uint64_t layers = count_[sample];
        // A full sample cannot add (a frame replayed again, FrameMemoryInputs::frames); an empty
        // one only can.
        appended = layers == 0 || (appended && layers < slots_);
        if (layers == 0) block_[sample] = blocks_++;
        const std::uint64_t header = headerBase_ + sample * kLayerHeaderBytes;
        lines(header, kLayerHeaderBytes, false, patch, memory);
        lines(blockOf(sample), layers * kLayerBytes, false, patch, memory);
        const std::uint64_t slot = appended ? layers : layers - 1;
        lines(blockOf(sample) + slot * kLayerBytes, kLayerBytes, true, patch, memory);
        memory.request(MemoryClass::LayerReads, kLayerHeaderBytes + layers * kLayerBytes);
        memory.request(MemoryClass::LayerWrites, kLayerBytes + (appended ? kLayerHeaderBytes : 0));
        if (!appended) return;
        lines(header, kLayerHeaderBytes, true, patch, memory);
        ++count_[sample];
    }
    // The resolve's reads of sample (x, y, s)'s header and layers; returns the bytes.
    std::uint64_t resolve(int x, int y, int s, std::size_t patch, MemorySystem& memory) const {
        if (slots_ == 0) return 0;
        const std::uint64_t sample = layout_.sampleIndex(x, y, s);
        const std::uint64_t bytes = std::uint64_t(count_[sample]) * kLayerBytes;
        lines(headerBase_ + sample * kLayerHeaderBytes, kLayerHeaderBytes, false, patch, memory);
        lines(blockOf(sample), bytes, false, patch, memory);
        return kLayerHeaderBytes + bytes;
    }

  private:
    std::uint64_t blockOf(std::uint64_t sample) const {
        return blockBase_ + std::uint64_t(block_[sample]) * slots_ * kLayerBytes;
    }
    static void lines(std::uint64_t at, std::uint64_t bytes, bool write, std::size_t patch,
                      MemorySystem& memory) {
        if (bytes == 0) return;
        for (std::uint64_t line = memory.lineOf(at); line <= memory.lineOf(at + bytes - 1); ++line)
            memory.access(CacheClient::Layers, line, write, patch);
    }
    const SurfaceLayout& layout_;
    std::uint64_t slots_, headerBase_, blockBase_, end_;
    std::vector<std::uint8_t> count_;   // per sample, its layers so far
    std::vector<std::uint32_t> block_;  // per sample with layers, its block
    std::uint32_t blocks_ = 0;
};

// Hierarchy bytes beyond the scratch budget, per patch, each at its own address after the
// layers.
class Spills {
  public:
    Spills(const std::vector<std::uint64_t>& bytes, std::uint64_t base) : bytes_(bytes) {
        begin_.reserve(bytes.size() + 1);
        std::uint64_t at = base;
        for (std::uint64_t b : bytes) {
            begin_.push_back(at);
            at = alignUp(at + b);
        }
        begin_.push_back(at);
    }
    std::uint64_t endAddress() const { return begin_.back(); }
    // Written once, in patch order, as the hierarchies are built.
    void write(std::size_t p, MemorySystem& memory) const {
        if (p >= bytes_.size() || bytes_[p] == 0) return;
        memory.newPass();
        for (std::uint64_t line : lines(memory, p)) memory.streamWrite(line, p);
        memory.request(MemoryClass::SpillWrites, bytes_[p]);
    }
    // Read back by one of the patch's tile passes.
    void read(std::size_t patch, MemorySystem& memory) const {
        if (patch >= bytes_.size() || bytes_[patch] == 0) return;
        for (std::uint64_t line : lines(memory, patch)) memory.readLastLevel(line, patch);
        memory.request(MemoryClass::SpillReads, bytes_[patch]);
    }

  private:
    struct LineRange {
        std::uint64_t first, last;
        struct Iterator {
            std::uint64_t line;
            std::uint64_t operator*() const { return line; }
            Iterator& operator++() {
                ++line;
                return *this;
            }
            bool operator!=(const Iterator& o) const { return line != o.line; }
        };
        Iterator begin() const { return {first}; }
        Iterator end() const { return {last + 1}; }
    };
    LineRange lines(const MemorySystem& memory, std::size_t p) const {
        return {memory.lineOf(begin_[p]), memory.lineOf(begin_[p] + bytes_[p] - 1)};
    }
    const std::vector<std::uint64_t>& bytes_;
    std::vector<std::uint64_t> begin_;
};

// The scene's index and vertex buffers, after the spills, and the input assembler's reads of
// them.
class InputBuffers {
  public:
    InputBuffers(const ControlPointFetch* fetch, std::uint64_t base)
        : fetch_(fetch ? *fetch : kNoFetch),
          indexBase_(base),
          vertexBase_(alignUp(base + fetch_.vertices.size() * kIndexBytes)),
          end_(alignUp(vertexBase_ + fetch_.vertexCount * kControlPointBytes)) {}
    std::uint64_t endAddress() const { return end_; }
    void markInDram(MemorySystem& memory) const {
        if (end_ > indexBase_)
            memory.markInDram(memory.lineOf(indexBase_), memory.lineOf(end_ - 1));
    }
    // Patch `p`'s indices, then its control points, through the vertex input cache.
    void read(std::size_t p, MemorySystem& memory) const {
        if (p >= fetch_.patches()) return;
        const std::uint64_t begin = fetch_.patchBegin[p], end = fetch_.patchBegin[p + 1];
        if (begin == end) return;
        memory.newPass();
        readBytes(indexBase_ + begin * kIndexBytes, (end - begin) * kIndexBytes, p, memory);
        for (std::uint64_t k = begin; k < end; ++k)
            readBytes(vertexBase_ + std::uint64_t(fetch_.vertices[k]) * kControlPointBytes,
                      kControlPointBytes, p, memory);
        memory.request(MemoryClass::IndexReads, (end - begin) * kIndexBytes);
        memory.request(MemoryClass::ControlPointReads, (end - begin) * kControlPointBytes);
    }

  private:
    static void readBytes(std::uint64_t at, std::uint64_t bytes, std::size_t p,
                          MemorySystem& memory) {
        for (std::uint64_t line = memory.lineOf(at); line <= memory.lineOf(at + bytes - 1); ++line)
            memory.access(CacheClient::VertexInput, line, false, p);
    }
    static inline const ControlPointFetch kNoFetch{};
    const ControlPointFetch& fetch_;
    std::uint64_t indexBase_, vertexBase_, end_;
};

// A z test's read of sample (x, y, s)'s depth.
void readDepth(const SurfaceLayout& layout, int x, int y, int s, std::size_t patch,
               MemorySystem& memory) {
    memory.access(CacheClient::Depth, memory.lineOf(layout.depthAddress(x, y, s)), false, patch);
}

// A nearer hit at sample (x, y, s): its depth and the rest of its record written.
void writeHit(const SurfaceLayout& layout, int x, int y, int s, std::size_t patch,
              MemorySystem& memory) {
    memory.access(CacheClient::Depth, memory.lineOf(layout.depthAddress(x, y, s)), true, patch);
    const std::uint64_t v = layout.visibilityAddress(x, y, s);
    for (std::uint64_t line = memory.lineOf(v); line <= memory.lineOf(v + kVisibilityBytes - 1);
         ++line)
        memory.access(CacheClient::Visibility, line, true, patch);
}

// What a pass's z-test reads and nearer hits ask of memory.
void requestZTests(std::size_t reads, std::size_t writes, MemorySystem& memory) {
    memory.request(MemoryClass::DepthReads, reads * kDepthBytes);
    memory.request(MemoryClass::DepthWrites, writes * kDepthBytes);
    memory.request(MemoryClass::VisibilityWrites, writes * kVisibilityBytes);
}

// One pass of the trace: its reads, writes and offers through the caches.
void replayPass(const MemoryTrace& trace, const SurfaceLayout& layout, const Spills& spills,
                LayerBuffer& layers, std::size_t r, std::size_t p, MemorySystem& memory) {
    const auto spp = std::size_t(trace.samplesPerPixel());
    const RegionTrace& region = trace.region(r);
    const auto stride = std::size_t(region.stride);
    // A sample's number in its region, in screen coordinates (core/memory_trace.h).
    const auto at = [&](std::uint32_t local) {
        const std::size_t pixel = local / spp;
        return std::array<int, 3>{region.x0 + int(pixel % stride), region.y0 + int(pixel / stride),
                                  int(local % spp)};
    };
    const std::size_t patch = region.passes[p].patch;
    memory.newPass();
    spills.read(patch, memory);
    const std::span<const std::uint32_t> reads = trace.reads(region, p);
    const std::span<const std::uint32_t> writes = trace.writes(region, p);
    for (std::uint32_t local : reads) {
        const auto [x, y, s] = at(local);
        readDepth(layout, x, y, s, patch, memory);
    }
    for (std::uint32_t local : writes) {
        const auto [x, y, s] = at(local);
        writeHit(layout, x, y, s, patch, memory);
    }
    requestZTests(reads.size(), writes.size(), memory);
    for (std::uint32_t offer : trace.offers(region, p)) {
        const auto [x, y, s] = at(offer & ~kAppended);
        layers.offer(x, y, s, (offer & kAppended) != 0, patch, memory);
    }
}

// A pass of the trace, by its patch, region and place in the region.
struct PassAt {
    std::uint32_t patch, region, pass;
};

// Every pass of the trace in patch order, each patch's in region order (the screen's tiles
// row-major, or its bands top to bottom).
std::vector<PassAt> passesInPatchOrder(const MemoryTrace& trace) {
    std::vector<PassAt> passes;
    for (std::size_t r = 0; r < trace.regionCount(); ++r)
        for (std::size_t p = 0; p < trace.region(r).passes.size(); ++p)
            passes.push_back({trace.region(r).passes[p].patch, std::uint32_t(r), std::uint32_t(p)});
    std::stable_sort(passes.begin(), passes.end(),
                     [](const PassAt& a, const PassAt& b) { return a.patch < b.patch; });
    return passes;
}

// A trace's reads and writes of each pass regrouped by sample index (a counting sort per pass,
// once), each as its pixel's number in the region, so that index s's replay visits its own only.
class PassesByIndex {
  public:
    explicit PassesByIndex(const MemoryTrace& trace) : spp_(std::size_t(trace.samplesPerPixel())) {
        for (std::size_t r = 0; r < trace.regionCount(); ++r) {
            const RegionTrace& region = trace.region(r);
            reads_.push_back(
                regroup(region, [&](std::size_t p) { return trace.reads(region, p); }));
            writes_.push_back(
                regroup(region, [&](std::size_t p) { return trace.writes(region, p); }));
        }
    }
    std::span<const std::uint32_t> reads(std::size_t r, std::size_t p, std::size_t s) const {
        return reads_[r].of(p * spp_ + s);
    }
    std::span<const std::uint32_t> writes(std::size_t r, std::size_t p, std::size_t s) const {
        return writes_[r].of(p * spp_ + s);
    }

  private:
    struct Lists {
        std::vector<std::uint32_t> pixels;
        std::vector<std::uint32_t> begin;  // list k: [begin[k], begin[k + 1]); a trace's lists
                                           // are 32-bit indexed (TracedPass)
        std::span<const std::uint32_t> of(std::size_t k) const {
            return {pixels.data() + begin[k], std::size_t(begin[k + 1] - begin[k])};
        }
    };
    template <class PassList>
    Lists regroup(const RegionTrace& region, PassList list) const {
        Lists out;
        out.begin.assign(region.passes.size() * spp_ + 1, 0);
        for (std::size_t p = 0; p < region.passes.size(); ++p)
            for (std::uint32_t local : list(p)) ++out.begin[p * spp_ + local % spp_ + 1];
        for (std::size_t k = 1; k < out.begin.size(); ++k) out.begin[k] += out.begin[k - 1];
        out.pixels.resize(out.begin.back());
        std::vector<std::uint32_t> next(out.begin.begin(), out.begin.end() - 1);
        for (std::size_t p = 0; p < region.passes.size(); ++p)
            for (std::uint32_t local : list(p))
                out.pixels[next[p * spp_ + local % spp_]++] = std::uint32_t(local / spp_);
        return out;
    }
    std::size_t spp_;
    std::vector<Lists> reads_, writes_;  // per region
};

// Sample index s of the accumulation buffer's pass p of region r (memory_model.h): its reads
// and writes, onto the pixel's one sample of `layout` (at 1 spp).
void replayIndexPass(const MemoryTrace& trace, const PassesByIndex& byIndex,
                     const SurfaceLayout& layout, std::size_t r, std::size_t p, std::size_t s,
                     MemorySystem& memory) {
    const RegionTrace& region = trace.region(r);
    const auto stride = std::uint32_t(region.stride);
    const std::size_t patch = region.passes[p].patch;
    const auto x = [&](std::uint32_t pixel) { return region.x0 + int(pixel % stride); };
    const auto y = [&](std::uint32_t pixel) { return region.y0 + int(pixel / stride); };
    memory.newPass();
    const std::span<const std::uint32_t> reads = byIndex.reads(r, p, s);
    const std::span<const std::uint32_t> writes = byIndex.writes(r, p, s);
    for (std::uint32_t pixel : reads) readDepth(layout, x(pixel), y(pixel), 0, patch, memory);
    for (std::uint32_t pixel : writes) writeHit(layout, x(pixel), y(pixel), 0, patch, memory);
    requestZTests(reads.size(), writes.size(), memory);
}

// The accumulation buffer's frame: per sample index the front end, the passes, the resolve into
// the accumulation buffer at `accumulation` and a fast clear; then the image (memory_model.h).
void replayAccumulation(const MemoryTrace& trace, const SurfaceLayout& layout,
                        const InputBuffers& inputs, std::uint64_t accumulation, MemoryOrder order,
                        std::size_t patches, std::size_t lastPatch, bool frontEnd,
                        MemorySystem& memory) {
    const auto pixelLines = [&](CacheClient client, std::uint64_t at, std::uint64_t bytes) {
        for (std::uint64_t line = memory.lineOf(at); line <= memory.lineOf(at + bytes - 1); ++line)
            memory.access(client, line, false, lastPatch);
    };
    // The accumulation buffer goes through the last-level cache, a line at a time: read (once a
    // line), then written whole as its pixels are written in order.
    std::uint64_t lastRead = ~std::uint64_t(0);
    const auto readAccumulation = [&](std::uint64_t at) {
        for (std::uint64_t line = memory.lineOf(at);
             line <= memory.lineOf(at + kAccumulationPixelBytes - 1); ++line)
            if (line != lastRead) memory.readLastLevel(lastRead = line, lastPatch);
    };
    const auto writeAccumulation = [&](std::uint64_t at) {
        for (std::uint64_t line = memory.lineOf(at);
             line <= memory.lineOf(at + kAccumulationPixelBytes - 1); ++line)
            memory.streamWrite(line, lastPatch);
    };
    const auto accumulationAddress = [&](int x, int y) {
        return accumulation + (std::uint64_t(y) * std::uint64_t(trace.width()) + std::uint64_t(x)) *
                                  kAccumulationPixelBytes;
    };
    const auto pixels = std::uint64_t(trace.width()) * std::uint64_t(trace.height());
    const PassesByIndex byIndex(trace);
    const std::vector<PassAt> passes =
        order == MemoryOrder::Patches ? passesInPatchOrder(trace) : std::vector<PassAt>{};
    for (int s = 0; s < trace.samplesPerPixel(); ++s) {
        const auto pass = [&](const PassAt& at) {
            replayIndexPass(trace, byIndex, layout, at.region, at.pass, std::size_t(s), memory);
        };
        if (order == MemoryOrder::Regions) {
            // Sort-middle: the front end runs ahead of the bands.
            if (frontEnd)
                for (std::size_t p = 0; p < patches; ++p) inputs.read(p, memory);
            for (std::uint32_t r = 0; r < trace.regionCount(); ++r)
                for (std::uint32_t p = 0; p < trace.region(r).passes.size(); ++p) pass({0, r, p});
        } else {
            // A patch at a time: fetched, then its passes in band order.
            auto next = passes.begin();
            for (std::size_t p = 0; p < patches; ++p) {
                if (frontEnd) inputs.read(p, memory);
                for (; next != passes.end() && next->patch == p; ++next) pass(*next);
            }
            for (; next != passes.end(); ++next) pass(*next);
        }
        // The pass's resolve: each pixel's sample read and added into the accumulation buffer.
        memory.newPass();
        for (int y = 0; y < trace.height(); ++y)
            for (int x = 0; x < trace.width(); ++x) {
                pixelLines(CacheClient::Depth, layout.depthAddress(x, y, 0), kDepthBytes);
                pixelLines(CacheClient::Visibility, layout.visibilityAddress(x, y, 0),
                           kVisibilityBytes);
                if (s > 0) readAccumulation(accumulationAddress(x, y));
                writeAccumulation(accumulationAddress(x, y));
            }
        memory.request(MemoryClass::ResolveReads, pixels * (kDepthBytes + kVisibilityBytes));
        if (s > 0) memory.request(MemoryClass::AccumulationReads, pixels * kAccumulationPixelBytes);
        memory.request(MemoryClass::AccumulationWrites, pixels * kAccumulationPixelBytes);
        // The next index starts from cleared surfaces: this one's are dead.
        memory.discard(memory.lineOf(layout.depthAddress(0, 0, 0)),
                       memory.lineOf(layout.imageAddress(0, 0) - 1));
        lastRead = ~std::uint64_t(0);
    }
    memory.newPass();
    for (int y = 0; y < trace.height(); ++y)
        for (int x = 0; x < trace.width(); ++x) {
            readAccumulation(accumulationAddress(x, y));
            memory.streamWrite(memory.lineOf(layout.imageAddress(x, y)), lastPatch);
        }
    memory.request(MemoryClass::AccumulationReads, pixels * kAccumulationPixelBytes);
    memory.request(MemoryClass::ImageWrites, pixels * kImagePixelBytes);
}

// What a frame's replay runs before a patch's passes: the input assembler's fetch and the
// hierarchy's spill written. A warm repeat runs neither; a later frame rebuilds the hierarchies
// from the front end's output, which it does not fetch again.
struct FrontEndTraffic {
    bool fetch = true, spills = true;
};

// The front end's traffic and every pass, in the order of `order` (MemoryOrder).
void replayPasses(const MemoryTrace& trace, const SurfaceLayout& layout, const Spills& spills,
                  const InputBuffers& inputs, LayerBuffer& layers, MemoryOrder order,
                  std::size_t patches, FrontEndTraffic frontEnd, MemorySystem& memory) {
    const auto runFrontEnd = [&](std::size_t p) {
        if (frontEnd.fetch) inputs.read(p, memory);
        if (frontEnd.spills) spills.write(p, memory);
    };
    if (order == MemoryOrder::Regions) {
        // Sort-middle: the front end runs ahead of the regions.
        for (std::size_t p = 0; p < patches; ++p) runFrontEnd(p);
        for (std::size_t r = 0; r < trace.regionCount(); ++r)
            for (std::size_t p = 0; p < trace.region(r).passes.size(); ++p)
                replayPass(trace, layout, spills, layers, r, p, memory);
        return;
    }
    // A patch at a time: fetched, its hierarchy built, then its passes in region order (the
    // screen's tiles row-major, or its bands top to bottom).
    const std::vector<PassAt> passes = passesInPatchOrder(trace);
    auto next = passes.begin();
    for (std::size_t p = 0; p < patches; ++p) {
        runFrontEnd(p);
        for (; next != passes.end() && next->patch == p; ++next)
            replayPass(trace, layout, spills, layers, next->region, next->pass, memory);
    }
    // A pass charged to a patch past the frame's count (a hand-made trace) still runs.
    for (; next != passes.end(); ++next)
        replayPass(trace, layout, spills, layers, next->region, next->pass, memory);
}

// Every sample's record read, pixel by pixel, and the image written.
void replayResolve(const MemoryTrace& trace, const SurfaceLayout& layout, const LayerBuffer& layers,
                   std::size_t patch, MemorySystem& memory) {
    const int spp = trace.samplesPerPixel();
    memory.newPass();
    const auto lines = [&](CacheClient client, std::uint64_t begin, std::uint64_t bytes) {
        for (std::uint64_t line = memory.lineOf(begin); line <= memory.lineOf(begin + bytes - 1);
             ++line)
            memory.access(client, line, false, patch);
    };
    std::uint64_t layerBytes = 0;
    for (int y = 0; y < trace.height(); ++y)
        for (int x = 0; x < trace.width(); ++x) {
            lines(CacheClient::Depth, layout.depthAddress(x, y, 0),
                  std::uint64_t(spp) * kDepthBytes);
            lines(CacheClient::Visibility, layout.visibilityAddress(x, y, 0),
                  std::uint64_t(spp) * kVisibilityBytes);
            for (int s = 0; s < spp; ++s) layerBytes += layers.resolve(x, y, s, patch, memory);
            memory.streamWrite(memory.lineOf(layout.imageAddress(x, y)), patch);
        }
    const auto pixels = std::uint64_t(trace.width()) * std::uint64_t(trace.height());
    memory.request(MemoryClass::ResolveReads,
                   pixels * std::uint64_t(spp) * (kDepthBytes + kVisibilityBytes) + layerBytes);
    memory.request(MemoryClass::ImageWrites, pixels * kImagePixelBytes);
}

// The image-space passes after the resolve (core/image_pass_trace.h): plane 0 is the resolved
// image where the resolve wrote it; the rest lie from `base` on, one after another, each on a
// 4 KiB boundary. Every access goes through the image cache.
class ImagePlanes {
  public:
    // `imageBases`: where each resolved frame's image lies.
    ImagePlanes(const ImagePassTrace* trace, const std::vector<std::uint64_t>& imageBases,
                std::uint64_t base)
        : trace_(trace), end_(base) {
        if (!trace_) return;
        for (const ImagePlane& plane : trace_->planes()) {
            if (bases_.size() < std::size_t(trace_->resolvedFrames())) {
                bases_.push_back(imageBases.at(bases_.size()));
                continue;
            }
            bases_.push_back(end_);
            end_ = alignUp(end_ + plane.elements * plane.elementBytes);
        }
    }
    std::uint64_t endAddress() const { return end_; }

    // Consecutive accesses of a pass to one line of a plane are one access, plane by plane (a
    // pass reads its planes as separate streams: a tap's colour, depth and velocity lie in
    // three lines, and the next tap's colour most often in the first again).
    void replay(std::size_t patch, MemorySystem& memory) const {
        if (!trace_) return;
        const std::vector<ImagePlane>& planes = trace_->planes();
        using LastLines = std::array<std::array<std::uint64_t, 2>, kMaxImagePlanes>;
        for (const ImagePass& pass : trace_->passes()) {
            memory.newPass();
            LastLines last;
            for (auto& plane : last) plane.fill(CacheModel::kEmpty);
            for (std::size_t i = 0; i < pass.elements.size(); ++i) {
                const std::uint16_t mask = pass.planes[i];
                const bool write = accessWrites(mask);
                for (std::size_t p = 0; p < planes.size(); ++p) {
                    if (!(mask >> p & 1u)) continue;
                    const std::uint64_t at =
                        bases_[p] + std::uint64_t(pass.elements[i]) * planes[p].elementBytes;
                    for (std::uint64_t line = memory.lineOf(at);
                         line <= memory.lineOf(at + planes[p].elementBytes - 1); ++line) {
                        if (line == last[p][write]) continue;
                        last[p][write] = line;
                        memory.access(CacheClient::Image, line, write, patch);
                    }
                }
            }
            memory.request(MemoryClass::ImagePassReads, trace_->passBytes(pass, false));
            memory.request(MemoryClass::ImagePassWrites, trace_->passBytes(pass, true));
        }
    }

  private:
    const ImagePassTrace* trace_;
    std::vector<std::uint64_t> bases_;
    std::uint64_t end_;
};

}  // namespace

const char* memoryClassName(MemoryClass c) {
    return kClassInfo[std::size_t(c)].name;
}
const char* memoryClassDefinition(MemoryClass c) {
    return kClassInfo[std::size_t(c)].definition;
}

SurfaceLayout::SurfaceLayout(int width, int height, int samplesPerPixel, int surfaceTile,
                             std::uint64_t base)
    : width_(width),
      height_(height),
      spp_(samplesPerPixel),
      tile_(surfaceTile),
      blocksX_((width + surfaceTile - 1) / surfaceTile) {
    const auto blocksY = std::uint64_t((height + surfaceTile - 1) / surfaceTile);
    samplesPadded_ = std::uint64_t(blocksX_) * blocksY * std::uint64_t(tile_) *
                     std::uint64_t(tile_) * std::uint64_t(spp_);
    depthBase_ = base;
    visibilityBase_ = alignUp(base + samplesPadded_ * kDepthBytes);
    imageBase_ = alignUp(visibilityBase_ + samplesPadded_ * kVisibilityBytes);
}

std::uint64_t SurfaceLayout::sampleIndex(int x, int y, int sample) const {
    const auto block =
        std::uint64_t(y / tile_) * std::uint64_t(blocksX_) + std::uint64_t(x / tile_);
    const auto inBlock = std::uint64_t(y % tile_) * std::uint64_t(tile_) + std::uint64_t(x % tile_);
    return (block * std::uint64_t(tile_) * std::uint64_t(tile_) + inBlock) * std::uint64_t(spp_) +
           std::uint64_t(sample);
}

std::uint64_t SurfaceLayout::endAddress() const {
    return imageBase_ + std::uint64_t(width_) * std::uint64_t(height_) * kImagePixelBytes;
}

std::vector<std::uint64_t> hierarchySpills(const std::vector<PatchOps>& patches,
                                           std::uint64_t scratchBudgetBytes) {
    std::vector<std::uint64_t> spills(patches.size(), 0);
    for (std::size_t p = 0; p < patches.size(); ++p)
        if (patches[p].hierarchyBytes > scratchBudgetBytes)
            spills[p] = patches[p].hierarchyBytes - scratchBudgetBytes;
    return spills;
}

namespace {

// Every dirty line written back (charged to the frame's last patch), and the report.
MemoryReport finishReplay(const MemoryTrace& trace, const MemoryConfig& config,
                          const FrameMemoryInputs& frame, MemorySystem& memory) {
    memory.writeBack(frame.lastPatch);
    MemoryReport report = memory.finish();
    report.patches.resize(frame.patchCount);
    report.traceBytes = trace.bytes();
    report.config = config;
    return report;
}

// The accumulation buffer's frame (memory_model.h): surfaces at 1 spp, the accumulation buffer
// after them, then the scene's buffers; no layers (transparent frames are not recorded), no
// spills (the bounding methods build no hierarchy), no depth compression and no image-space
// passes (the interleaved method runs none).
MemoryReport simulateAccumulation(const MemoryTrace& trace, const MemoryConfig& config,
                                  const FrameMemoryInputs& frame) {
    const SurfaceLayout layout(trace.width(), trace.height(), 1, config.surfaceTile);
    const std::uint64_t accumulation = alignUp(layout.endAddress());
    const InputBuffers inputs(
        frame.fetch,
        alignUp(accumulation + std::uint64_t(trace.width()) * std::uint64_t(trace.height()) *
                                   kAccumulationPixelBytes));
    const std::size_t patches = std::max(frame.patchCount, frame.lastPatch + 1);
    const std::uint64_t depthBlockBytes =
        std::uint64_t(config.surfaceTile) * std::uint64_t(config.surfaceTile) * kDepthBytes;
    const std::vector<double> uncompressed;  // a pass's depth lives one pass: not compressed
    MemorySystem memory(config, inputs.endAddress(), patches, uncompressed, depthBlockBytes);
    inputs.markInDram(memory);
    for (int f = 0; f < frame.frames; ++f)
        replayAccumulation(trace, layout, inputs, accumulation, config.order, patches,
                           frame.lastPatch, f == 0, memory);
    return finishReplay(trace, config, frame, memory);
}

}  // namespace

MemoryReport simulateMemory(const MemoryTrace& trace, const MemoryConfig& config,
                            const FrameMemoryInputs& frame) {
    if (trace.accumulation()) return simulateAccumulation(trace, config, frame);
    const SurfaceLayout layout(trace.width(), trace.height(), trace.samplesPerPixel(),
                               config.surfaceTile);
    LayerBuffer layers(trace, layout, alignUp(layout.endAddress()));
    const Spills spills(frame.spillBytes, layers.endAddress());
    const std::size_t patches = std::max(frame.patchCount, frame.lastPatch + 1);
    const std::uint64_t depthBlockBytes = std::uint64_t(config.surfaceTile) *
                                          std::uint64_t(config.surfaceTile) *
                                          std::uint64_t(trace.samplesPerPixel()) * kDepthBytes;
    const InputBuffers inputs(frame.fetch, spills.endAddress());
    // A later frame's surfaces and layers follow the scene's buffers, frame after frame (its
    // LayerBuffer keeps a reference to its layout: no reallocation).
    const std::vector<MemoryTrace>& later = trace.laterFrames();
    std::vector<SurfaceLayout> laterLayouts;
    std::vector<LayerBuffer> laterLayers;
    laterLayouts.reserve(later.size());
    laterLayers.reserve(later.size());
    std::vector<std::uint64_t> imageBases{layout.imageAddress(0, 0)};
    std::uint64_t end = inputs.endAddress();
    for (const MemoryTrace& t : later) {
        const SurfaceLayout& l = laterLayouts.emplace_back(
            t.width(), t.height(), t.samplesPerPixel(), config.surfaceTile, end);
        end = laterLayers.emplace_back(t, l, alignUp(l.endAddress())).endAddress();
        imageBases.push_back(l.imageAddress(0, 0));
    }
    const ImagePlanes images(trace.imagePasses(), imageBases, end);
    // A later frame's depth lies past the blocks `depthScale` describes: uncompressed.
    MemorySystem memory(config, images.endAddress(), patches, frame.depthScale, depthBlockBytes);
    inputs.markInDram(memory);
    for (int f = 0; f < frame.frames; ++f)
        replayPasses(trace, layout, spills, inputs, layers, config.order, patches, {f == 0, f == 0},
                     memory);
    replayResolve(trace, layout, layers, frame.lastPatch, memory);
    for (std::size_t k = 0; k < later.size(); ++k) {
        replayPasses(later[k], laterLayouts[k], spills, inputs, laterLayers[k], config.order,
                     patches, {false, true}, memory);
        if (later[k].resolved())
            replayResolve(later[k], laterLayouts[k], laterLayers[k], frame.lastPatch, memory);
    }
    images.replay(frame.lastPatch, memory);
    return finishReplay(trace, config, frame, memory);
}

nlohmann::ordered_json memoryReportJson(const MemoryReport& r) {
    nlohmann::ordered_json caches = nlohmann::ordered_json::object();
    for (int c = 0; c < kCacheClients; ++c) {
        const CacheStats& s = r.caches[std::size_t(c)];
        caches[cacheClientName(CacheClient(c))] = {
            {"reads", s.reads},          {"writes", s.writes},      {"read_hits", s.readHits},
            {"write_hits", s.writeHits}, {"hit_rate", s.hitRate()}, {"writebacks", s.writebacks}};
    }
    nlohmann::ordered_json requested = nlohmann::ordered_json::object();
    for (int c = 0; c < kMemoryClasses; ++c)
        requested[memoryClassName(MemoryClass(c))] = r.requestedBytes[std::size_t(c)];
    nlohmann::ordered_json json = {{"config", memoryConfigJson(r.config)},
                                   {"requested_bytes", requested},
                                   {"caches", caches},
                                   {"dram_read_bytes", r.dramReadBytes},
                                   {"dram_write_bytes", r.dramWriteBytes},
                                   {"dram_line_reads", r.dramReads},
                                   {"trace_bytes", r.traceBytes}};
    if (r.config.dramBanks.modelled()) {
        nlohmann::ordered_json limited = nlohmann::ordered_json::object();
        for (int k = 0; k < kDramLimits; ++k)
            limited[dramLimitName(DramLimit(k))] = r.dramBanks.cyclesLimitedBy[std::size_t(k)];
        json["dram_banks"] = {{"transfers", r.dramBanks.transfers},
                              {"row_hits", r.dramBanks.rowHits},
                              {"activations", r.dramBanks.activations},
                              {"row_hit_rate", r.dramBanks.rowHitRate()},
                              {"cycles_limited_by", limited}};
    }
    if (r.depthCompression) {
        const DepthCompressionReport& d = *r.depthCompression;
        json["depth_compression"] = {{"scheme", depthCompressionName(d.scheme)},
                                     {"blocks", d.blockBits.size()},
                                     {"clear_blocks", d.clearBlocks},
                                     {"compressed_bits", d.compressedBits},
                                     {"uncompressed_bits", d.uncompressedBits},
                                     {"ratio", d.ratio()}};
    }
    return json;
}

void printMemoryReport(const MemoryReport& r, std::ostream& out) {
    char line[160];
    out << "memory: requested bytes by class\n";
    for (int c = 0; c < kMemoryClasses; ++c) {
        std::snprintf(line, sizeof line, "  %-20s %14llu\n", memoryClassName(MemoryClass(c)),
                      static_cast<unsigned long long>(r.requestedBytes[std::size_t(c)]));
        out << line;
    }
    out << "  cache                line reads  line writes   hit rate  write-backs      bytes  "
           "ways\n";
    for (int c = 0; c < kCacheClients; ++c) {
        const CacheStats& s = r.caches[std::size_t(c)];
        const CacheGeometry& g = r.config.caches[std::size_t(c)].geometry;
        std::snprintf(line, sizeof line, "  %-18s %12llu %12llu %9.1f%% %12llu %10llu %5u%s\n",
                      cacheClientTitle(CacheClient(c)), static_cast<unsigned long long>(s.reads),
                      static_cast<unsigned long long>(s.writes), 100.0 * s.hitRate(),
                      static_cast<unsigned long long>(s.writebacks),
                      static_cast<unsigned long long>(g.sizeBytes), g.ways,
                      r.config.cacheGiven[std::size_t(c)] ? "" : " (derived)");
        out << line;
    }
    std::snprintf(line, sizeof line, "  order: %s\n", memoryOrderName(r.config.order));
    out << line;
    std::snprintf(line, sizeof line, "  DRAM: %llu bytes read, %llu bytes written\n",
                  static_cast<unsigned long long>(r.dramReadBytes),
                  static_cast<unsigned long long>(r.dramWriteBytes));
    out << line;
    if (const DramBankConfig& b = r.config.dramBanks; b.modelled()) {
        const DramBankStats& d = r.dramBanks;
        const double all = d.cyclesLimitedBy[0] + d.cyclesLimitedBy[1] + d.cyclesLimitedBy[2];
        const auto share = [&](DramLimit k) {
            return all > 0 ? 100.0 * d.cyclesLimitedBy[std::size_t(k)] / all : 0.0;
        };
        std::snprintf(line, sizeof line,
                      "  DRAM: %d channels x %d banks, rows of %u bytes: %llu transfers, %.1f%% "
                      "row hits, %llu activations\n",
                      b.channels, b.banks, b.rowBytes, static_cast<unsigned long long>(d.transfers),
                      100.0 * d.rowHitRate(), static_cast<unsigned long long>(d.activations));
        out << line;
        std::snprintf(line, sizeof line,
                      "  DRAM time limited by the bus %.1f%%, a bank %.1f%%, activations "
                      "(t_rrd) %.1f%%\n",
                      share(DramLimit::Bus), share(DramLimit::Bank), share(DramLimit::Activations));
        out << line;
    }
    if (r.depthCompression) {
        const DepthCompressionReport& d = *r.depthCompression;
        std::snprintf(line, sizeof line,
                      "  depth compression (%s): %.1f%% of the uncompressed size over the %zu "
                      "blocks holding geometry (%.2f bits a sample); %llu clear blocks\n",
                      depthCompressionName(d.scheme), 100.0 * d.ratio(),
                      d.blockBits.size() - std::size_t(d.clearBlocks), 32.0 * d.ratio(),
                      static_cast<unsigned long long>(d.clearBlocks));
        out << line;
    }
}

}  // namespace patchsim
