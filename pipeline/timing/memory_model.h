#pragma once
// The memory system of the modelled hardware: a frame's per-sample surface traffic, replayed
// from the rasterizer's trace (core/memory_trace.h) through the caches of a MemoryConfig to DRAM,
// giving measured hit rates, bytes per data class and each patch's memory work for the timing
// model (DESIGN.md section 8, docs/HARDWARE.md "Memory").
//
// Representation
// --------------
// Three surfaces, each in a tiled layout: depth (4 bytes a sample), visibility (the rest of a
// sample's record: patch, triangle, two barycentrics, time, lens u and v, 28 bytes) and the final
// image (8 bytes a pixel: RGBA at 16 bits). A per-sample surface is cut into blocks of
// `surfaceTile` x `surfaceTile` pixels, blocks row-major, pixels row-major in a block, a pixel's
// samples consecutive; the image is row-major. Each surface starts on a 4 KiB boundary, depth
// first.
//
// The order of the replay is the modelled hardware's: the trace's regions in order, each
// region's passes in order (the patch method: screen tiles row-major, each tile's groups in patch
// order, a sort-middle rasterizer working one screen tile at a time as the functional rasterizer
// does; triangle-bbox and interval: bands of rows top to bottom, each band's triangles in patch
// order), then the resolve (every sample's depth and visibility read, pixel by pixel, and the
// image written), then the caches written back. A pass's z test reads its samples' depth lines;
// a nearer hit writes the sample's depth and visibility lines. A miss fetches its line from the
// last-level cache, and a last-level miss from DRAM, unless the line is still in its cleared
// state (the frame's surfaces start cleared: fast clear, nothing to fetch). Dirty lines evicted
// go one level down; the LLC's reach DRAM (at their line's address, through its channels and
// banks when the section models them: dram_banks.h). Each access is charged to the patch of its
// pass (the resolve and the final write-back to the frame's last patch), so the timing model sees
// each patch's line accesses per cache and DRAM bytes.
//
// Before the tiles, in patch order, the input assembler fetches each patch's control points
// through the vertex input cache: their cage vertex indices from an index buffer (4 bytes each,
// a patch's consecutive) and then each vertex's position from a vertex buffer (12 bytes, every
// object's cage one after another), both after the spills; neighbouring patches share vertices,
// so the cache and the LLC catch the repeats. These buffers are the scene's, in DRAM before the
// frame starts.
//
// With transparency (a trace with layer slots) the layers follow the image: a header per
// sample (4 bytes: its block and its layer count, in the per-sample surfaces' tiled order), then
// blocks of K layers of 32 bytes (a layer fragment: the record and its object), given out in the
// order samples first get a layer. An offer reads the sample's header and its layers so far
// (the merge and the farthest-layer search of rasterizer/common/transparent_layers.h) and writes
// one layer, and the header too when it adds a layer (an upper bound: an offer that merged with
// or lost to a nearer layer may write nothing). The resolve reads each sample's header and
// layers. All of it goes through the layer cache.
//
// An accumulation buffer's trace (MemoryTrace::accumulation, the interleaved method) is
// replayed as the modelled hardware renders it: a whole frame per sample index s. Its surfaces
// hold one sample a pixel (the same tiled layout at 1 spp), and an accumulation buffer of
// 16 bytes a pixel follows them. For each index the front end fetches every patch again and
// the passes run with their index-s reads and writes only, onto the pixel's one sample, in the
// memory order (`regions`: every fetch, then the bands; `patches`: each patch fetched, then its
// passes band by band); then a
// resolve reads each pixel's depth and record, adds its colour into the accumulation buffer (a
// read, but for the first index, and a write), and a fast clear drops the dead depth and
// visibility lines from every cache without writing them back. After the last index the
// accumulation buffer is read once more and the image written. Transparent frames are not
// replayed this way (the render records no trace for them), and depth is not compressed. A
// warm repeat (FrameMemoryInputs::frames) runs every index again without the fetches.
//
// A later frame (MemoryTrace::laterFrames: reprojection's frame at shutter close) has surfaces
// and layers of its own after the scene's buffers, laid out as the first frame's; its passes
// follow the first frame's resolve, without the fetch (the front end's output is reused) but with
// the spills written again (its hierarchies are built again), then its resolve.
//
// An image-space method's full-screen passes (MemoryTrace::imagePasses, core/image_pass_trace.h)
// follow the resolves, access by access through the image cache: the first planes are the
// resolved images where the resolves wrote them, the method's other planes lie after the later
// frames, row-major, each on a 4 KiB boundary. Consecutive accesses of a pass to one line of a
// plane are one access.
//
// A patch whose hierarchy outgrows the on-chip scratch budget spills the excess: written once
// through the LLC when the hierarchy is built (before the tiles, in patch order), read again
// through the LLC by each of the patch's tile passes (all of it: an upper bound, as which nodes a
// tile test visits is not traced). The spills lie after the layers, patch after patch.

#include <array>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <ostream>
#include <vector>

#include "core/memory_trace.h"
#include "core/stage_ops.h"
#include "pipeline/timing/depth_compression.h"
#include "pipeline/timing/hardware_config.h"

namespace patchsim {

// What each data class asked of the memory system, in bytes (before the caches).
#define PATCHSIM_MEMORY_CLASSES(X)                                                               \
    X(DepthReads, "depth_reads", "z-test reads of a sample's depth (4 bytes)")                   \
    X(DepthWrites, "depth_writes", "depth of a nearer hit (4 bytes)")                            \
    X(VisibilityWrites, "visibility_writes", "the rest of its record (28 bytes)")                \
    X(ResolveReads, "resolve_reads", "the resolve's reads of every sample's record, layers")     \
    X(ImageWrites, "image_writes", "the final image, 8 bytes a pixel")                           \
    X(SpillWrites, "spill_writes", "hierarchy bytes beyond the scratch budget, written once")    \
    X(SpillReads, "spill_reads", "those bytes read again by each of the patch's tile passes")    \
    X(IndexReads, "index_reads", "a patch's control-point indices (4 bytes each)")               \
    X(ControlPointReads, "control_point_reads", "its control points' cage positions (12 bytes)") \
    X(LayerReads, "layer_reads", "an offer's reads of a sample's layer header and its layers")   \
    X(LayerWrites, "layer_writes", "an offer's layer written (32 bytes), and header when added") \
    X(AccumulationReads, "accumulation_reads",                                                   \
      "an accumulation buffer's pixel read to add a pass, and at the end (16 bytes)")            \
    X(AccumulationWrites, "accumulation_writes", "its pixel written after each pass (16 bytes)") \
    X(ImagePassReads, "image_pass_reads",                                                        \
      "image-space passes' reads of the resolved image and their planes")                        \
    X(ImagePassWrites, "image_pass_writes", "their planes written, the resolve's AOVs too")

enum class MemoryClass : std::uint8_t {
#define PATCHSIM_MEMORY_CLASS_ENUM(name, key, definition) name,
    PATCHSIM_MEMORY_CLASSES(PATCHSIM_MEMORY_CLASS_ENUM)
#undef PATCHSIM_MEMORY_CLASS_ENUM
};
inline constexpr int kMemoryClasses = 15;
const char* memoryClassName(MemoryClass c);
const char* memoryClassDefinition(MemoryClass c);

inline constexpr std::uint32_t kDepthBytes = 4, kVisibilityBytes = 28, kImagePixelBytes = 8;
inline constexpr std::uint32_t kIndexBytes = 4, kControlPointBytes = 12;
inline constexpr std::uint32_t kLayerHeaderBytes = 4, kLayerBytes = 32;
inline constexpr std::uint32_t kAccumulationPixelBytes = 16;  // RGBA at 32 bits
static_assert(kImagePixelBytes == kResolvedImagePixelBytes,
              "an image-space pass reads the resolved image where the resolve wrote it");

// What the input assembler fetches for each patch, in patch order: its control points' indices
// into the scene's vertex buffer (every object's cage vertices, object after object).
struct ControlPointFetch {
    std::vector<std::uint64_t> patchBegin;  // patch p's indices: [patchBegin[p], patchBegin[p + 1])
    std::vector<std::uint32_t> vertices;
    std::uint64_t vertexCount = 0;  // in the vertex buffer
    std::size_t patches() const { return patchBegin.empty() ? 0 : patchBegin.size() - 1; }
};

// One patch's memory work: line accesses per cache and bytes moved to and from DRAM.
struct PatchMemory {
    std::array<std::uint64_t, kCacheClients> lineAccesses{};
    std::uint64_t dramBytes = 0;
    std::uint64_t dramReads = 0;  // lines read from DRAM
    // With DRAM banks: its DRAM time (DramBanks::patchTimes).
    double dramCycles = 0;
};

struct MemoryReport {
    std::array<CacheStats, kCacheClients> caches{};
    std::array<std::uint64_t, kMemoryClasses> requestedBytes{};
    std::uint64_t dramReadBytes = 0, dramWriteBytes = 0;
    std::uint64_t dramReads = 0;  // lines read from DRAM
    DramBankStats dramBanks;      // with DRAM banks modelled
    std::vector<PatchMemory> patches;
    std::uint64_t traceBytes = 0;
    // With depth compression: the frame's final depth, block by block.
    std::optional<DepthCompressionReport> depthCompression;
    MemoryConfig config;  // what the frame was replayed through

    std::uint64_t dramBytes() const { return dramReadBytes + dramWriteBytes; }
    std::uint64_t requested(MemoryClass c) const { return requestedBytes[std::size_t(c)]; }
};

// Where the per-sample surfaces and the image lie (see the essay above).
class SurfaceLayout {
  public:
    // `base`: where the depth surface starts (a later frame's surfaces lie after the first's).
    SurfaceLayout(int width, int height, int samplesPerPixel, int surfaceTile,
                  std::uint64_t base = 0);
    std::uint64_t sampleIndex(int x, int y, int sample) const;
    std::uint64_t depthAddress(int x, int y, int s) const {
        return depthBase_ + sampleIndex(x, y, s) * kDepthBytes;
    }
    std::uint64_t visibilityAddress(int x, int y, int s) const {
        return visibilityBase_ + sampleIndex(x, y, s) * kVisibilityBytes;
    }
    std::uint64_t imageAddress(int x, int y) const {
        return imageBase_ +
               (std::uint64_t(y) * std::uint64_t(width_) + std::uint64_t(x)) * kImagePixelBytes;
    }
    std::uint64_t endAddress() const;
    std::uint64_t samples() const { return samplesPadded_; }  // with the blocks' padding

  private:
    int width_, height_, spp_, tile_, blocksX_;
    std::uint64_t samplesPadded_, depthBase_, visibilityBase_, imageBase_;
};

// What the replay needs beside the trace: the patch count, the patch that takes the resolve and
// the final write-back (the frame's last), and per patch the hierarchy bytes that did not fit
// the scratch budget (empty: none spilled).
struct FrameMemoryInputs {
    std::size_t patchCount = 0;
    std::size_t lastPatch = 0;
    std::vector<std::uint64_t> spillBytes{};
    int frames = 1;  // > 1: the passes again onto the surfaces as they stand (warm caches)
    // With depth compression: per layout block of the depth surface, its compressed size over
    // its uncompressed size, which its lines move at to and from DRAM (empty: uncompressed;
    // DepthCompressionReport::blockScales).
    std::vector<double> depthScale{};
    const ControlPointFetch* fetch = nullptr;  // null: no front-end traffic (a bare trace)
};

// Per patch, its largest hierarchy's bytes beyond `scratchBudgetBytes`.
std::vector<std::uint64_t> hierarchySpills(const std::vector<PatchOps>& patches,
                                           std::uint64_t scratchBudgetBytes);

// The frame's traffic through `config`'s caches.
MemoryReport simulateMemory(const MemoryTrace& trace, const MemoryConfig& config,
                            const FrameMemoryInputs& frame);

// stats.json's "memory" object (docs/COUNTERS.md) and the printed report.
nlohmann::ordered_json memoryReportJson(const MemoryReport& report);
void printMemoryReport(const MemoryReport& report, std::ostream& out);

}  // namespace patchsim
