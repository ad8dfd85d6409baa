#pragma once
// The modelled hardware's energy per frame (issue 35, docs/HARDWARE.md "Energy"): every counted
// operation at the energy of the arithmetic it does, every cache line access at its SRAM's
// energy, every DRAM byte at DRAM's.
//
// Representation
// --------------
// `EnergyTable` holds picojoules at 45 nm and 0.9 V (Horowitz, ISSCC 2014, the defaults): an add
// and a multiply in fp32 and fp16 and in 8- and 32-bit integers, a 64-bit read of an SRAM of
// 8 KiB, 32 KiB and 1 MiB, a 64-bit DRAM access, and the overhead a programmable shader pays per
// arithmetic operation (instruction fetch, decode and register file), with one factor that
// scales every entry to another process node. Between and beyond its points an SRAM's access
// energy follows the size on a log-log line; an integer add's energy is linear in its width and
// a multiply's a power of it (about the square: an array multiplier), through the table's points.
//
// `OpArithmetic` is what one operation of a kind (core/stage_ops.h) does in the functional code:
// floating-point adds, multiplies, compares (a min, max or select counts one) and divides (a
// reciprocal too), integer adds and multiplies at a width, and operand bytes read from the
// stage's on-chip buffers (the hierarchy scratch, the domain-shaded triangles). A fused
// multiply-add is a multiply and an add. Float work is charged in the site's number format
// (fp32 everywhere until a site's format is configurable); a compare costs an add, a divide four
// multiplies (a reciprocal's Newton-Raphson steps, the iso-arithmetic file's weight).
//
// A frame's energy: per stage, its counted operations times their arithmetic's energy, plus for
// the programmable stages (VS, HS, DS, PS) the shader overhead per arithmetic operation, plus
// their operand bytes at the on-chip scratch's SRAM energy; with the memory system modelled,
// each cache's line accesses times (line bytes / 8) times the 64-bit access energy at its size,
// and DRAM's bytes / 8 times the DRAM access energy.

#include <array>
#include <nlohmann/json_fwd.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "core/json_fields.h"
#include "core/number_format.h"
#include "core/stage_ops.h"

namespace patchsim {

struct HardwareConfig;
struct MemoryReport;
inline constexpr int kEnergyMemoryParts = 7;  // the caches (memory_model.h's order), then DRAM

// X(member, "json key", default picojoules at 45 nm, "what one costs")
#define PATCHSIM_ENERGY_ENTRIES(X)                                                              \
    X(fp32Add, "fp32_add_pj", 0.9, "fp32 add, subtract or compare")                             \
    X(fp32Multiply, "fp32_mul_pj", 3.7, "fp32 multiply")                                        \
    X(fp16Add, "fp16_add_pj", 0.4, "fp16 add, subtract or compare")                             \
    X(fp16Multiply, "fp16_mul_pj", 1.1, "fp16 multiply")                                        \
    X(int8Add, "int8_add_pj", 0.03, "8-bit integer add")                                        \
    X(int32Add, "int32_add_pj", 0.1, "32-bit integer add")                                      \
    X(int8Multiply, "int8_mul_pj", 0.2, "8-bit integer multiply")                               \
    X(int32Multiply, "int32_mul_pj", 3.1, "32-bit integer multiply")                            \
    X(sram8KiB, "sram_8kib_read_pj", 10.0, "64-bit read of an 8 KiB SRAM")                      \
    X(sram32KiB, "sram_32kib_read_pj", 20.0, "64-bit read of a 32 KiB SRAM")                    \
    X(sram1MiB, "sram_1mib_read_pj", 100.0, "64-bit read of a 1 MiB SRAM")                      \
    X(dramAccess, "dram_access_pj", 1950.0, "64-bit DRAM access (Horowitz: 1300 to 2600)")      \
    X(shaderOverhead, "shader_overhead_pj", 8.0,                                                \
      "a programmable stage's overhead per arithmetic operation: Horowitz's instruction fetch " \
      "and control (64 pJ) shared by a 32-wide SIMD, and a register file access (6 pJ)")

struct EnergyTable {
#define PATCHSIM_ENERGY_MEMBER(member, key, value, what) double member = value;
    PATCHSIM_ENERGY_ENTRIES(PATCHSIM_ENERGY_MEMBER)
#undef PATCHSIM_ENERGY_MEMBER
    double processScale = 1;  // every entry's factor: 1 at 45 nm

    double floatAdd(const NumberFormat& f) const;       // bf16 at fp16's cost, fixed as integer
    double floatMultiply(const NumberFormat& f) const;  // the same
    double intAdd(int bits) const;
    double intMultiply(int bits) const;
    double sramRead64(double sizeBytes) const;  // log-log through the three sizes
};

// What one operation of a kind does (see the essay above).
struct OpArithmetic {
    Op op = Op::Patches;
    double adds = 0, multiplies = 0, compares = 0, divides = 0;
    double intAdds = 0, intMultiplies = 0;
    int intBits = 32;
    double operandBytes = 0;
    const char* how = "";

    double operations() const {
        return adds + multiplies + compares + divides + intAdds + intMultiplies;
    }
};
const OpArithmetic& opArithmetic(Op op);
bool isProgrammable(Stage s);  // VS, HS, DS and PS run shaders

// Picojoules of one operation of `op` on `table` (the scratch `scratchBytes`, its operand bytes
// times `operandScale`, its arithmetic in `arithmetic`, `copies` times over).
double opPicojoules(Op op, const EnergyTable& table, double scratchBytes, double operandScale = 1,
                    const NumberFormat& arithmetic = NumberFormat::fp32(), int copies = 1);

// The formats of issue 35's sites (docs/PRECISION.md): what the three storage sites store
// (rasterizer.node_format, rasterizer.screen_bounds_format, rasterizer.vertex_format) and what
// the three computing sites compute in (rasterizer.plane_format, rasterizer.ray_box_format,
// rasterizer.triangle_format).
struct SiteFormats {
    NumberFormat nodes, screenBounds, vertices, planes, rayBoxes, triangles;
};

struct EnergyReport {
    std::array<double, kStageCount> stagePicojoules{};
    std::array<double, kEnergyMemoryParts> memoryPicojoules{};  // zero without the memory model
    bool memoryModelled = false;
    double triangles = 0;  // the tessellator's, for the energy per triangle
    EnergyTable table;     // what the frame was priced at
    SiteFormats formats;

    double computePicojoules() const;
    double memoryTotalPicojoules() const;
    double totalPicojoules() const { return computePicojoules() + memoryTotalPicojoules(); }
};

// The frame's energy from its counted operations (summed over patches) and, when given, its
// memory traffic. With `formats` narrower than fp32, the operations that read the hierarchy's
// boxes (nodes_built, plane_tests, ray_box_tests) or the domain-shaded positions
// (ray_triangle_tests, triangle_setups, edge_setups) move that many bits a value instead of 32.
// With a narrower plane format, plane_tests and time_intervals compute in it, twice over: the
// value and its error bound (tile_frustum_rounded.h); ray_box_tests likewise in a narrower ray-box
// format; ray_triangle_tests once (rounded to nearest, no bound) in a narrower triangle format.
EnergyReport estimateEnergy(const std::vector<PatchOps>& patches, const HardwareConfig& hardware,
                            const MemoryReport* memory, const SiteFormats& formats = {});

// The hardware file's optional "energy" section: any entry by its key (PATCHSIM_ENERGY_ENTRIES)
// and "process_scale", each finite and positive; the rest keep their defaults. Throws InputError
// naming the field.
EnergyTable readEnergyTable(ObjectReader reader);
// Sets one entry ("fp32_mul_pj", "process_scale") as an `explore` grid point does.
void setEnergyEntry(EnergyTable& table, const std::string& key, const nlohmann::json& value,
                    const std::string& source, const std::string& field);
nlohmann::ordered_json energyTableJson(const EnergyTable& table);
nlohmann::ordered_json energyReportJson(const EnergyReport& report);
void printEnergyReport(const EnergyReport& report, std::ostream& out);

}  // namespace patchsim
