#pragma once
// The simulated hardware: per pipeline stage, its units, throughput per operation kind, latency
// and input FIFO depth, plus the on-chip scratch budget for one patch hierarchy and the clock.
// Read from JSON (docs/HARDWARE.md); the default ships as pipeline/hw/default.json and is built
// into the binary.

#include <array>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

namespace patchsim {

enum class Stage : std::uint8_t { IA, VS, HS, TS, DS, RS, PS, OM };
inline constexpr int kStageCount = 8;
const char* stageName(Stage s);

// Operation kinds the timing model charges, each done by one stage.
enum class Op : std::uint8_t {
    Patches,               // IA
    ControlPoints,         // VS
    EdgeFactors,           // HS
    DomainPoints,          // TS
    Triangles,             // TS
    Evaluations,           // DS: limit stencils evaluated
    StencilApplications,   // DS
    NodesBuilt,            // RS: hierarchy nodes
    PlaneTests,            // RS
    TimeIntervals,         // RS
    SamplesTested,         // RS
    RayBoxTests,           // RS
    RayTriangleTests,      // RS
    Invocations,           // PS
    DepthTests,            // OM: visibility samples written
    TransparentFragments,  // OM
    TriangleSetups,        // RS: triangle screen bounds (the bounding-box methods)
    PostSamples            // PS: post-process passes' pixel reads (TileMax, gather)
};
inline constexpr int kOpCount = 18;
const char* opName(Op op);  // the JSON key, e.g. "ray_box_tests"
Stage stageOf(Op op);

struct StageConfig {
    int units = 1;
    double latency = 0;  // cycles from a patch's last operation to its delivery downstream
    int fifoDepth = 4;   // patches the FIFO in front of this stage holds
    std::array<double, kOpCount> throughput{};  // per unit per clock, for this stage's op kinds
};

struct HardwareConfig {
    double clockGHz = 1.0;
    std::uint64_t scratchBudgetBytes = 16 * 1024;
    std::array<StageConfig, kStageCount> stages;

    const StageConfig& stage(Stage s) const { return stages[std::size_t(s)]; }
    StageConfig& stage(Stage s) { return stages[std::size_t(s)]; }
};

// Throws InputError naming the file and field ("stages.RS.throughput.ray_box_tests").
HardwareConfig parseHardwareConfig(std::string_view text, const std::string& path);
HardwareConfig readHardwareConfig(const std::string& path);
HardwareConfig defaultHardwareConfig();  // pipeline/hw/default.json

// Sets one parameter by its path ("RS.units", "RS.throughput.ray_box_tests", "RS.latency",
// "RS.fifo_depth", "clock_ghz", "scratch_budget_bytes") to a JSON value, with the ranges the file
// reader applies; throws InputError(source, field) if the path is unknown or the value refused.
void setHardwareParameter(HardwareConfig& config, const std::string& path,
                          const nlohmann::json& value, const std::string& source,
                          const std::string& field);

}  // namespace patchsim
