#pragma once
// The simulated hardware: per pipeline stage, its units, throughput per operation kind, latency
// and input FIFO depth, plus the on-chip scratch budget for one patch hierarchy and the clock.
// Read from JSON (docs/HARDWARE.md); the default ships as pipeline/hw/default.json and is built
// into the binary.

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/stage_ops.h"
#include "pipeline/timing/cache_model.h"
#include "pipeline/timing/depth_compression.h"
#include "pipeline/timing/dram_banks.h"
#include "pipeline/timing/energy_model.h"

namespace patchsim {

struct StageConfig {
    int units = 1;
    double latency = 0;  // cycles from a patch's last operation to its delivery downstream
    int fifoDepth = 4;   // patches the FIFO in front of this stage holds
    std::array<double, kOpCount> throughput{};  // per unit per clock, for this stage's op kinds
};

// The caches of the memory system, each a client of the last-level cache but the LLC itself
// (always the last).
enum class CacheClient : std::uint8_t { Depth, Visibility, VertexInput, Layers, Image, LastLevel };
inline constexpr int kCacheClients = 6;
const char* cacheClientName(CacheClient c);   // its key in the hardware file: "depth", ...
const char* cacheClientTitle(CacheClient c);  // in reports: "depth cache", ...

// The order the modelled rasterizer works a frame's passes in (docs/HARDWARE.md, "Memory"):
// `Regions`, a screen region at a time, as the functional rasterizer does (the patch method's
// tiles, the bounding methods' bands), each region's passes in patch order; `Patches`, a patch at
// a time across the screen, as an immediate-mode rasterizer that holds one patch's hierarchy in
// its scratch does.
enum class MemoryOrder : std::uint8_t { Regions, Patches };
const char* memoryOrderName(MemoryOrder o);  // "regions", "patches"

struct CacheConfig {
    CacheGeometry geometry;
    double linesPerClock = 1;  // line accesses the cache serves per clock
};

// The memory system (docs/HARDWARE.md, "Memory"): per-sample surfaces in a tiled layout, a
// depth and a visibility cache, the input assembler's vertex input cache and the transparent
// layers' cache in front of a shared last-level cache, and DRAM.
struct MemoryConfig {
    int surfaceTile = 8;  // pixels per side of a layout block of the per-sample surfaces
    MemoryOrder order = MemoryOrder::Regions;
    std::array<CacheConfig, kCacheClients> caches;
    double dramBytesPerClock = 32;
    double dramLatency = 200;  // cycles from a patch's last memory request to its data
    DramBankConfig dramBanks;  // banks and rows (dram_banks.h); none: an ideal bus
    // DRAM line reads the memory system keeps outstanding at once; 0: no limit.
    std::uint32_t dramReadsInFlight = 0;
    int fifoDepth = 8;  // patches waiting for the memory system
    // Depth blocks reach DRAM at their compressed size (depth_compression.h).
    DepthCompression depthCompression = DepthCompression::None;

    // The caches the file gave; an optional one left out (vertex_input, layers, image) is derived
    // from the others whenever the section is read, so an `explore` point that changes those
    // changes it too.
    std::array<bool, kCacheClients> cacheGiven{true, true, true, true, true, true};

    const CacheConfig& cache(CacheClient c) const { return caches[std::size_t(c)]; }
    CacheConfig& cache(CacheClient c) { return caches[std::size_t(c)]; }
    std::uint32_t lineBytes() const { return caches[0].geometry.lineBytes; }
};

struct HardwareConfig {
    double clockGHz = 1.0;
    std::uint64_t scratchBudgetBytes = 16 * 1024;
    std::array<StageConfig, kStageCount> stages;
    // Absent: the compute-only model (infinite bandwidth, no memory traffic simulated).
    std::optional<MemoryConfig> memory;
    EnergyTable energy;  // the file's optional "energy" section over Horowitz's 45 nm defaults

    const StageConfig& stage(Stage s) const { return stages[std::size_t(s)]; }
    StageConfig& stage(Stage s) { return stages[std::size_t(s)]; }
};

// Throws InputError naming the file and field ("stages.RS.throughput.ray_box_tests").
HardwareConfig parseHardwareConfig(std::string_view text, const std::string& path);
HardwareConfig readHardwareConfig(const std::string& path);
HardwareConfig defaultHardwareConfig();  // pipeline/hw/default.json

// Sets one parameter by its path ("RS.units", "RS.throughput.ray_box_tests", "RS.latency",
// "RS.fifo_depth", "clock_ghz", "scratch_budget_bytes", or a field of the memory section such as
// "memory.dram.bytes_per_clock" or "memory.caches.depth.size_bytes", or an energy entry such as
// "energy.fp32_mul_pj" or "energy.process_scale") to a JSON value, with the
// ranges the file reader applies; throws InputError(source, field) if the path is unknown or the
// value refused.
void setHardwareParameter(HardwareConfig& config, const std::string& path,
                          const nlohmann::json& value, const std::string& source,
                          const std::string& field);

// Several at once (an `explore` grid point): the memory section's fields are set together and
// checked as a whole, so a cache's size and ways can change together. "memory.line_bytes" sets
// every cache's line size.
struct HardwareParameter {
    std::string path;
    nlohmann::json value;
    std::string field;
};
void setHardwareParameters(HardwareConfig& config, const std::vector<HardwareParameter>& parameters,
                           const std::string& source);

// The memory section as the model uses it: every cache, the derived ones filled in (stats.json's
// memory.config).
nlohmann::json memoryConfigJson(const MemoryConfig& memory);

}  // namespace patchsim
