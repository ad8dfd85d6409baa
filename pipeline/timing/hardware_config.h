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

#include "core/stage_ops.h"

namespace patchsim {

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
