#include "pipeline/timing/energy_model.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "pipeline/timing/hardware_config.h"
#include "pipeline/timing/memory_model.h"

namespace patchsim {

namespace {

constexpr double kKiB = 1024;

// Entries by key, for the reader and the JSON.
struct Entry {
    const char* key;
    double EnergyTable::*member;
};
constexpr Entry kEntries[] = {
#define PATCHSIM_ENERGY_ENTRY(member, key, value, what) {key, &EnergyTable::member},
    PATCHSIM_ENERGY_ENTRIES(PATCHSIM_ENERGY_ENTRY)
#undef PATCHSIM_ENERGY_ENTRY
        {"process_scale", &EnergyTable::processScale},
};

constexpr double kEntryMin = 1e-12, kEntryMax = 1e9;  // picojoules, or the scale factor

// The share of 32 bits a value of `op`'s operands takes in its storage site's format.
double operandScale(Op op, const SiteFormats& formats) {
    switch (op) {
        case Op::PlaneTests:  // a 2D bounds space's tile tests read its stored screen boxes
            if (formats.screenBounds != NumberFormat::fp32())
                return storageBits(formats.screenBounds) / 32.0;
            return storageBits(formats.nodes) / 32.0;
        case Op::NodesBuilt:
        case Op::RayBoxTests:
            return storageBits(formats.nodes) / 32.0;
        case Op::RayTriangleTests:
        case Op::TriangleSetups:
        case Op::EdgeSetups:
            return storageBits(formats.vertices) / 32.0;
        default:
            return 1.0;
    }
}

// The format `op`'s arithmetic runs in: a computing site's (plane_format, ray_box_format,
// triangle_format), else fp32.
NumberFormat arithmeticFormat(Op op, const SiteFormats& formats) {
    if (op == Op::PlaneTests || op == Op::TimeIntervals) return formats.planes;
    if (op == Op::RayBoxTests) return formats.rayBoxes;
    if (op == Op::RayTriangleTests) return formats.triangles;
    return NumberFormat::fp32();
}

double linear(double x, double x0, double y0, double x1, double y1) {
    return y0 + (x - x0) * (y1 - y0) / (x1 - x0);
}

}  // namespace

bool isProgrammable(Stage s) {
    return s == Stage::VS || s == Stage::HS || s == Stage::DS || s == Stage::PS;
}

double EnergyTable::intAdd(int bits) const {
    return processScale * std::max(0.0, linear(bits, 8, int8Add, 32, int32Add));
}

double EnergyTable::intMultiply(int bits) const {
    // A power of the width through the 8- and 32-bit points: an array multiplier's energy grows
    // about with the square of its width (Horowitz's points give an exponent of 1.98).
    const double exponent = std::log(int32Multiply / int8Multiply) / std::log(4.0);
    return processScale * int32Multiply * std::pow(bits / 32.0, exponent);
}

double EnergyTable::floatAdd(const NumberFormat& f) const {
    switch (f.kind) {
        case NumberFormat::Kind::Fp32:
            return processScale * fp32Add;
        case NumberFormat::Kind::Fp16:
        case NumberFormat::Kind::Bf16:
            return processScale * fp16Add;
        case NumberFormat::Kind::Fixed:
            return intAdd(f.integerBits + f.fractionBits);
    }
    return processScale * fp32Add;
}

double EnergyTable::floatMultiply(const NumberFormat& f) const {
    switch (f.kind) {
        case NumberFormat::Kind::Fp32:
            return processScale * fp32Multiply;
        case NumberFormat::Kind::Fp16:
        case NumberFormat::Kind::Bf16:
            return processScale * fp16Multiply;
        case NumberFormat::Kind::Fixed:
            return intMultiply(f.integerBits + f.fractionBits);
    }
    return processScale * fp32Multiply;
}

double EnergyTable::sramRead64(double sizeBytes) const {
    // log E against log size through (8 KiB, 32 KiB, 1 MiB); beyond them the nearest segment's
    // slope continues (about the square root of the size: a wire across the array).
    const double x = std::log(std::max(sizeBytes, 1.0));
    const double x8 = std::log(8 * kKiB), x32 = std::log(32 * kKiB), x1m = std::log(1024 * kKiB);
    const double y8 = std::log(sram8KiB), y32 = std::log(sram32KiB), y1m = std::log(sram1MiB);
    const double y = x <= x32 ? linear(x, x8, y8, x32, y32) : linear(x, x32, y32, x1m, y1m);
    return processScale * std::exp(y);
}

double opPicojoules(Op op, const EnergyTable& table, double scratchBytes, double operandScale,
                    const NumberFormat& arithmetic, int copies) {
    const OpArithmetic& a = opArithmetic(op);
    double pj = copies * ((a.adds + a.compares) * table.floatAdd(arithmetic) +
                          (a.multiplies + 4 * a.divides) * table.floatMultiply(arithmetic)) +
                a.intAdds * table.intAdd(a.intBits) +
                a.intMultiplies * table.intMultiply(a.intBits) +
                a.operandBytes * operandScale / 8 * table.sramRead64(scratchBytes);
    if (isProgrammable(stageOf(op)))
        pj += a.operations() * table.processScale * table.shaderOverhead;
    return pj;
}

double EnergyReport::computePicojoules() const {
    double sum = 0;
    for (double pj : stagePicojoules) sum += pj;
    return sum;
}

double EnergyReport::memoryTotalPicojoules() const {
    double sum = 0;
    for (double pj : memoryPicojoules) sum += pj;
    return sum;
}

EnergyReport estimateEnergy(const std::vector<PatchOps>& patches, const HardwareConfig& hardware,
                            const MemoryReport* memory, const SiteFormats& formats) {
    static_assert(kEnergyMemoryParts == kCacheClients + 1);
    PatchOps total;
    for (const PatchOps& p : patches) total.add(p);
    EnergyReport report;
    report.table = hardware.energy;
    report.formats = formats;
    const EnergyTable& table = hardware.energy;
    for (int k = 0; k < kOpCount; ++k) {
        const Op op = Op(k);
        const NumberFormat arithmetic = arithmeticFormat(op, formats);
        // A bounded site computes its value and its error bound; the triangle test rounds
        // to nearest with no bound.
        const bool bounded = arithmetic != NumberFormat::fp32() && op != Op::RayTriangleTests;
        const int copies = bounded ? 2 : 1;
        report.stagePicojoules[std::size_t(stageOf(op))] +=
            total.ops[std::size_t(k)] * opPicojoules(op, table, double(hardware.scratchBudgetBytes),
                                                     operandScale(op, formats), arithmetic, copies);
    }
    report.triangles = total[Op::Triangles];
    if (!memory) return report;
    report.memoryModelled = true;
    for (int c = 0; c < kCacheClients; ++c) {
        const CacheGeometry& g = memory->config.caches[std::size_t(c)].geometry;
        report.memoryPicojoules[std::size_t(c)] =
            double(memory->caches[std::size_t(c)].accesses()) * (g.lineBytes / 8.0) *
            table.sramRead64(double(g.sizeBytes));
    }
    report.memoryPicojoules[kCacheClients] =
        double(memory->dramBytes()) / 8.0 * table.processScale * table.dramAccess;
    return report;
}

EnergyTable readEnergyTable(ObjectReader reader) {
    EnergyTable table;
    for (const Entry& e : kEntries)
        table.*e.member = reader.number(e.key, table.*e.member, kEntryMin, kEntryMax);
    reader.finish();
    return table;
}

void setEnergyEntry(EnergyTable& table, const std::string& key, const nlohmann::json& value,
                    const std::string& source, const std::string& field) {
    for (const Entry& e : kEntries) {
        if (key != e.key) continue;
        Json section = {{key, value}};
        try {
            table.*e.member =
                ObjectReader(section, "", source).number(key, 0, kEntryMin, kEntryMax);
        } catch (const InputError& error) {  // the caller's name for the field
            throw InputError(source, field, error.message());
        }
        return;
    }
    throw InputError(source, field, "unknown hardware parameter 'energy." + key + "'");
}

nlohmann::ordered_json energyTableJson(const EnergyTable& table) {
    nlohmann::ordered_json json;
    for (const Entry& e : kEntries) json[e.key] = table.*e.member;
    return json;
}

nlohmann::ordered_json energyReportJson(const EnergyReport& report) {
    nlohmann::ordered_json stages = nlohmann::ordered_json::object();
    for (int s = 0; s < kStageCount; ++s)
        stages[stageName(Stage(s))] = report.stagePicojoules[std::size_t(s)] / 1e3;
    nlohmann::ordered_json json = {{"total_nj", report.totalPicojoules() / 1e3},
                                   {"compute_nj", report.computePicojoules() / 1e3},
                                   {"memory_modelled", report.memoryModelled},
                                   {"stages_nj", stages}};
    if (report.memoryModelled) {
        json["memory_nj"] = report.memoryTotalPicojoules() / 1e3;
        nlohmann::ordered_json parts = nlohmann::ordered_json::object();
        for (int c = 0; c < kCacheClients; ++c)
            parts[cacheClientTitle(CacheClient(c))] = report.memoryPicojoules[std::size_t(c)] / 1e3;
        parts["DRAM"] = report.memoryPicojoules[kCacheClients] / 1e3;
        json["memory_parts_nj"] = parts;
    }
    json["triangles"] = report.triangles;
    json["per_triangle_nj"] =
        report.triangles > 0 ? report.totalPicojoules() / 1e3 / report.triangles : 0.0;
    json["rasterizer_per_triangle_nj"] =
        report.triangles > 0
            ? report.stagePicojoules[std::size_t(Stage::RS)] / 1e3 / report.triangles
            : 0.0;
    json["node_format"] = formatName(report.formats.nodes);
    json["screen_bounds_format"] = formatName(report.formats.screenBounds);
    json["vertex_format"] = formatName(report.formats.vertices);
    json["plane_format"] = formatName(report.formats.planes);
    json["ray_box_format"] = formatName(report.formats.rayBoxes);
    json["triangle_format"] = formatName(report.formats.triangles);
    json["table"] = energyTableJson(report.table);
    return json;
}

void printEnergyReport(const EnergyReport& report, std::ostream& out) {
    const double total = report.totalPicojoules();
    const auto share = [&](double pj) {
        char text[64];
        std::snprintf(text, sizeof text, "%12.3f uJ  %5.1f%%", pj / 1e6,
                      total > 0 ? 100 * pj / total : 0.0);
        return std::string(text);
    };
    out << "energy: " << std::fixed << std::setprecision(2) << total / 1e6 << " uJ per frame"
        << (report.memoryModelled ? "" : " (arithmetic only: the hardware models no memory)")
        << "\n";
    for (int s = 0; s < kStageCount; ++s)
        out << "  " << std::left << std::setw(20) << stageName(Stage(s)) << std::right
            << share(report.stagePicojoules[std::size_t(s)]) << "\n";
    if (report.memoryModelled) {
        for (int c = 0; c < kCacheClients; ++c)
            out << "  " << std::left << std::setw(20) << cacheClientTitle(CacheClient(c))
                << std::right << share(report.memoryPicojoules[std::size_t(c)]) << "\n";
        out << "  " << std::left << std::setw(20) << "DRAM" << std::right
            << share(report.memoryPicojoules[kCacheClients]) << "\n";
    }
    if (report.triangles > 0)
        out << "  per triangle: " << std::setprecision(3) << total / 1e3 / report.triangles
            << " nJ, of it the rasterizer "
            << report.stagePicojoules[std::size_t(Stage::RS)] / 1e3 / report.triangles << " nJ\n";
    out << std::defaultfloat;
}

}  // namespace patchsim
