#include "pipeline/timing/hardware_config.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/json_fields.h"
#include "core/text_file.h"

namespace patchsim {

namespace {

int findOp(const std::string& name, Stage stage) {
    for (int k = 0; k < kOpCount; ++k)
        if (name == opName(Op(k)) && stageOf(Op(k)) == stage) return k;
    return -1;
}

// The accepted range of each parameter, shared by the file reader and setHardwareParameter.
struct Range {
    double lo, hi;
    bool integer;
};
constexpr Range kUnits{1, 1 << 20, true};
constexpr Range kLatency{0, 1e9, false};
constexpr Range kFifoDepth{1, 1 << 20, true};
constexpr Range kThroughput{1e-9, 1e9, false};
constexpr Range kClock{1e-6, 1e6, false};
constexpr Range kScratch{1, double(std::int64_t(1) << 40), true};

// A value in range as a double, or InputError(source, field).
double checked(const Json& j, const Range& range, const std::string& source,
               const std::string& field) {
    auto fail = [&](const std::string& why) { throw InputError(source, field, why); };
    if (range.integer && !j.is_number_integer())
        fail("expected an integer in [" + ObjectReader::formatNumber(range.lo) + ", " +
             ObjectReader::formatNumber(range.hi) + "], found " + j.dump());
    if (!j.is_number()) fail("expected a number, found " + j.dump());
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < range.lo || v > range.hi)
        fail("value " + j.dump() + " is outside [" + ObjectReader::formatNumber(range.lo) + ", " +
             ObjectReader::formatNumber(range.hi) + "]");
    return v;
}

void readStage(ObjectReader r, StageConfig& s, Stage stage) {
    if (const Json* j = r.find("units"))
        s.units = int(checked(*j, kUnits, r.file(), r.fieldName("units")));
    if (const Json* j = r.find("latency"))
        s.latency = checked(*j, kLatency, r.file(), r.fieldName("latency"));
    if (const Json* j = r.find("fifo_depth"))
        s.fifoDepth = int(checked(*j, kFifoDepth, r.file(), r.fieldName("fifo_depth")));
    if (auto t = r.object("throughput")) {
        for (int k = 0; k < kOpCount; ++k) {
            if (stageOf(Op(k)) != stage) continue;
            if (const Json* j = t->find(opName(Op(k))))
                s.throughput[std::size_t(k)] =
                    checked(*j, kThroughput, r.file(), t->fieldName(opName(Op(k))));
        }
        t->finish();
    }
    r.finish();
    for (int k = 0; k < kOpCount; ++k)
        if (stageOf(Op(k)) == stage && !(s.throughput[std::size_t(k)] > 0))
            r.fail(r.fieldName("throughput." + std::string(opName(Op(k)))),
                   "missing or not positive");
}

constexpr Range kSurfaceTile{1, 256, true};
constexpr Range kCacheBytes{1, double(std::int64_t(1) << 36), true};
constexpr Range kLineBytes{16, 4096, true};
constexpr Range kWays{1, 64, true};
constexpr Range kLinesPerClock{1e-9, 1e9, false};
constexpr Range kDramBytesPerClock{1e-9, 1e12, false};

CacheConfig readCache(ObjectReader r) {
    CacheConfig c;
    const auto need = [&](const char* key, const Range& range) {
        const Json* j = r.find(key);
        if (!j) r.fail(r.fieldName(key), "missing");
        return checked(*j, range, r.file(), r.fieldName(key));
    };
    c.geometry.sizeBytes = std::uint64_t(need("size_bytes", kCacheBytes));
    c.geometry.lineBytes = std::uint32_t(need("line_bytes", kLineBytes));
    c.geometry.ways = std::uint32_t(need("ways", kWays));
    c.linesPerClock = need("lines_per_clock", kLinesPerClock);
    const std::string policy = r.string("replacement", "lru");
    if (policy == "lru")
        c.geometry.replacement = Replacement::Lru;
    else if (policy == "fifo")
        c.geometry.replacement = Replacement::Fifo;
    else
        r.fail(r.fieldName("replacement"),
               "expected \"lru\" or \"fifo\", found \"" + policy + "\"");
    r.finish();
    const CacheGeometry& g = c.geometry;
    if (std::has_single_bit(g.lineBytes) == false)
        r.fail(r.fieldName("line_bytes"), "must be a power of two");
    // The simulation holds 9 bytes a line: 2^24 lines (a GiB of 64-byte lines) is 151 MB.
    constexpr std::uint64_t kMaxLines = std::uint64_t(1) << 24;
    if (g.sizeBytes / g.lineBytes > kMaxLines)
        r.fail(r.fieldName("size_bytes"), "at most " + std::to_string(kMaxLines) +
                                              " lines of line_bytes (" +
                                              std::to_string(kMaxLines * g.lineBytes) + " bytes)");
    const std::uint64_t setBytes = std::uint64_t(g.lineBytes) * g.ways;
    if (g.sizeBytes % setBytes != 0)
        r.fail(r.fieldName("size_bytes"), "must be a whole number of sets of line_bytes x ways = " +
                                              std::to_string(setBytes) + " bytes");
    return c;
}

// ATTILA's streamer input cache (bGPU.ini: 32 lines of 64 bytes), 4-way, at the memory's line
// size: what a memory section without a "vertex_input" cache gets.
CacheConfig defaultVertexInputCache(std::uint32_t lineBytes) {
    CacheConfig c;
    c.geometry.sizeBytes = 32 * std::uint64_t(lineBytes);
    c.geometry.lineBytes = lineBytes;
    c.geometry.ways = 4;
    c.geometry.replacement = Replacement::Lru;
    c.linesPerClock = 1;
    return c;
}

constexpr Range kChannels{1, 64, true};
constexpr Range kReadsInFlight{1, 1e6, true};
constexpr Range kBanks{1, 64, true};
constexpr Range kRowBytes{16, 1 << 20, true};
constexpr Range kDramTiming{0, 1e6, false};
constexpr const char* kBankFields[] = {"channels", "channel_bytes", "mapping", "row_bytes",
                                       "t_rcd",    "t_rp",          "t_rrd"};
constexpr int kMaxTotalBanks = 256;

// The channels, banks and rows of DRAM (dram_banks.h): with "banks", or none of them.
DramBankConfig readDramBanks(ObjectReader& dram, std::uint32_t lineBytes) {
    DramBankConfig b;
    const Json* banks = dram.find("banks");
    if (!banks) {
        for (const char* key : kBankFields)
            if (dram.find(key)) dram.fail(dram.fieldName(key), "given without \"banks\"");
        return b;
    }
    b.banks = int(checked(*banks, kBanks, dram.file(), dram.fieldName("banks")));
    const auto need = [&](const char* key, const Range& range) {
        const Json* j = dram.find(key);
        if (!j)
            dram.fail(dram.fieldName(key),
                      "missing (DRAM with banks needs row_bytes, t_rcd, t_rp and t_rrd)");
        return checked(*j, range, dram.file(), dram.fieldName(key));
    };
    const auto powerOfTwoOfLines = [&](const char* key, double value) {
        const auto bytes = std::uint32_t(value);
        if (!std::has_single_bit(bytes) || bytes < lineBytes)
            dram.fail(dram.fieldName(key), "must be a power of two of at least the line size (" +
                                               std::to_string(lineBytes) + " bytes)");
        return bytes;
    };
    if (const Json* j = dram.find("channels"))
        b.channels = int(checked(*j, kChannels, dram.file(), dram.fieldName("channels")));
    if (b.channels * b.banks > kMaxTotalBanks)
        dram.fail(dram.fieldName("banks"), "channels x banks must be at most " +
                                               std::to_string(kMaxTotalBanks) + ", found " +
                                               std::to_string(b.channels * b.banks));
    if (const Json* j = dram.find("channel_bytes"))
        b.channelBytes = powerOfTwoOfLines(
            "channel_bytes", checked(*j, kRowBytes, dram.file(), dram.fieldName("channel_bytes")));
    // Left out: 256 bytes, or a line if lines are longer (a line lies in one channel).
    b.channelBytes = std::max(b.channelBytes, lineBytes);
    b.rowBytes = powerOfTwoOfLines("row_bytes", need("row_bytes", kRowBytes));
    const std::string mapping = dram.string("mapping", "linear");
    if (mapping == "xor")
        b.mapping = DramMapping::Xor;
    else if (mapping != "linear")
        dram.fail(dram.fieldName("mapping"),
                  "expected \"linear\" or \"xor\", found \"" + mapping + "\"");
    if (b.mapping == DramMapping::Xor &&
        !(std::has_single_bit(unsigned(b.channels)) && std::has_single_bit(unsigned(b.banks))))
        dram.fail(dram.fieldName("mapping"),
                  "\"xor\" needs channels and banks that are powers of two, found " +
                      std::to_string(b.channels) + " x " + std::to_string(b.banks));
    b.activateCycles = need("t_rcd", kDramTiming);
    b.prechargeCycles = need("t_rp", kDramTiming);
    b.activateToActivateCycles = need("t_rrd", kDramTiming);
    return b;
}

MemoryConfig readMemory(ObjectReader r) {
    MemoryConfig m;
    if (const Json* j = r.find("surface_tile"))
        m.surfaceTile = int(checked(*j, kSurfaceTile, r.file(), r.fieldName("surface_tile")));
    if (const Json* j = r.find("fifo_depth"))
        m.fifoDepth = int(checked(*j, kFifoDepth, r.file(), r.fieldName("fifo_depth")));
    const std::string order = r.string("order", "regions");
    if (order == "patches")
        m.order = MemoryOrder::Patches;
    else if (order != "regions")
        r.fail(r.fieldName("order"),
               "expected \"regions\" or \"patches\", found \"" + order + "\"");
    const std::string compression = r.string("depth_compression", "none");
    if (!parseDepthCompression(compression, m.depthCompression))
        r.fail(r.fieldName("depth_compression"),
               "expected \"none\", \"plane\" or \"time_plane\", found \"" + compression + "\"");
    auto caches = r.object("caches");
    if (!caches) r.fail(r.fieldName("caches"), "missing the caches (depth, visibility, llc)");
    for (int c = 0; c < kCacheClients; ++c) {
        const char* name = cacheClientName(CacheClient(c));
        auto cache = caches->object(name);
        m.cacheGiven[std::size_t(c)] = cache.has_value();
        if (!cache && CacheClient(c) == CacheClient::VertexInput) {
            m.caches[std::size_t(c)] = defaultVertexInputCache(m.lineBytes());
            continue;
        }
        if (!cache && (CacheClient(c) == CacheClient::Layers ||
                       CacheClient(c) == CacheClient::Image)) {  // like the visibility cache
            m.caches[std::size_t(c)] = m.cache(CacheClient::Visibility);
            continue;
        }
        if (!cache) caches->fail(caches->fieldName(name), "missing cache");
        m.caches[std::size_t(c)] = readCache(*cache);
        if (m.caches[std::size_t(c)].geometry.lineBytes != m.lineBytes())
            caches->fail(caches->fieldName(std::string(name) + ".line_bytes"),
                         "every cache must have the depth cache's line size (" +
                             std::to_string(m.lineBytes()) + " bytes)");
    }
    caches->finish();
    auto dram = r.object("dram");
    if (!dram) r.fail(r.fieldName("dram"), "missing (bytes_per_clock, latency)");
    const Json* bandwidth = dram->find("bytes_per_clock");
    if (!bandwidth) dram->fail(dram->fieldName("bytes_per_clock"), "missing");
    m.dramBytesPerClock =
        checked(*bandwidth, kDramBytesPerClock, r.file(), dram->fieldName("bytes_per_clock"));
    const Json* latency = dram->find("latency");
    if (!latency) dram->fail(dram->fieldName("latency"), "missing");
    m.dramLatency = checked(*latency, kLatency, r.file(), dram->fieldName("latency"));
    m.dramBanks = readDramBanks(*dram, m.lineBytes());
    if (const Json* j = dram->find("max_reads_in_flight"))
        m.dramReadsInFlight = std::uint32_t(
            checked(*j, kReadsInFlight, r.file(), dram->fieldName("max_reads_in_flight")));
    dram->finish();
    r.finish();
    return m;
}

Json dramJson(const MemoryConfig& m) {
    Json dram = {{"bytes_per_clock", m.dramBytesPerClock}, {"latency", m.dramLatency}};
    if (m.dramReadsInFlight > 0) dram["max_reads_in_flight"] = m.dramReadsInFlight;
    if (const DramBankConfig& b = m.dramBanks; b.modelled()) {
        dram["channels"] = b.channels;
        dram["channel_bytes"] = b.channelBytes;
        dram["mapping"] = dramMappingName(b.mapping);
        dram["banks"] = b.banks;
        dram["row_bytes"] = b.rowBytes;
        dram["t_rcd"] = b.activateCycles;
        dram["t_rp"] = b.prechargeCycles;
        dram["t_rrd"] = b.activateToActivateCycles;
    }
    return dram;
}

// The section as a file gives it: with `derived`, the caches the file left out too.
Json memoryJson(const MemoryConfig& m, bool derived) {
    Json caches = Json::object();
    for (int c = 0; c < kCacheClients; ++c) {
        if (!derived && !m.cacheGiven[std::size_t(c)]) continue;
        const CacheConfig& cache = m.caches[std::size_t(c)];
        caches[cacheClientName(CacheClient(c))] = {
            {"size_bytes", cache.geometry.sizeBytes},
            {"line_bytes", cache.geometry.lineBytes},
            {"ways", cache.geometry.ways},
            {"replacement", replacementName(cache.geometry.replacement)},
            {"lines_per_clock", cache.linesPerClock}};
    }
    return {{"surface_tile", m.surfaceTile},
            {"fifo_depth", m.fifoDepth},
            {"order", memoryOrderName(m.order)},
            {"depth_compression", depthCompressionName(m.depthCompression)},
            {"caches", caches},
            {"dram", dramJson(m)}};
}

// Sets "dram.latency" and the like (a path below "memory.") in the section's JSON; "line_bytes"
// sets every given cache's line size at once. A field of a cache the section leaves out gives it
// the cache as derived from the section so far (`derived`, memoryJson's).
void setInMemoryJson(Json& section, const std::string& path, const Json& value, const Json& derived,
                     const std::string& source, const std::string& field) {
    const auto unknown = [&] {
        throw InputError(source, field, "unknown hardware parameter 'memory." + path + "'");
    };
    if (path == "line_bytes") {
        for (auto& [name, cache] : section["caches"].items()) cache["line_bytes"] = value;
        return;
    }
    if (path.starts_with("caches.")) {
        const std::string name = path.substr(7, path.find('.', 7) - 7);
        if (!section["caches"].contains(name) && derived["caches"].contains(name))
            section["caches"][name] = derived["caches"][name];
    }
    Json* at = &section;
    std::size_t from = 0;
    for (std::size_t dot; (dot = path.find('.', from)) != std::string::npos; from = dot + 1) {
        const std::string key = path.substr(from, dot - from);
        if (!at->contains(key) || !(*at)[key].is_object()) unknown();
        at = &(*at)[key];
    }
    const std::string key = path.substr(from);
    // DRAM's optional fields may be set where the file left them out; the section's check
    // then names what else they need (banks need their timings).
    const bool optionalDramField =
        path == "dram.max_reads_in_flight" || path == "dram.banks" ||
        std::any_of(std::begin(kBankFields), std::end(kBankFields),
                    [&](const char* f) { return path == std::string("dram.") + f; });
    if (optionalDramField && !at->contains(key)) (*at)[key] = value;
    if (!at->contains(key) || (*at)[key].is_object()) unknown();  // a field, not a section
    (*at)[key] = value;
}

}  // namespace

void setHardwareParameters(HardwareConfig& c, const std::vector<HardwareParameter>& parameters,
                           const std::string& source) {
    std::vector<const HardwareParameter*> memory;
    for (const HardwareParameter& p : parameters) {
        if (p.path.starts_with("memory."))
            memory.push_back(&p);
        else
            setHardwareParameter(c, p.path, p.value, source, p.field);
    }
    if (memory.empty()) return;
    if (!c.memory)
        throw InputError(source, memory.front()->field,
                         "the hardware models no memory (its file has no \"memory\" section)");
    // Every memory field of the set at once, then the file's checks on the whole section: one
    // field's value may be right only with another's (a cache's size with its ways).
    Json section = memoryJson(*c.memory, false);
    // Fields of the caches the file left out last: they start from the rest as the point sets it.
    std::stable_partition(memory.begin(), memory.end(), [&](const HardwareParameter* p) {
        return !p->path.starts_with("memory.caches.") ||
               section["caches"].contains(p->path.substr(14, p->path.find('.', 14) - 14));
    });
    for (const HardwareParameter* p : memory) {
        Json derived = memoryJson(*c.memory, true);
        try {
            derived = memoryJson(readMemory(ObjectReader(section, "memory", source)), true);
        } catch (const InputError&) {
            // The section is checked as a whole below.
        }
        setInMemoryJson(section, p->path.substr(7), p->value, derived, source, p->field);
    }
    try {
        c.memory = readMemory(ObjectReader(section, "memory", source));
    } catch (const InputError& e) {
        // The reader names the section's own field: the caller's name for it, if it set it.
        const HardwareParameter* culprit = memory.front();
        for (const HardwareParameter* p : memory)
            if (p->path == e.field() ||
                (p->path == "memory.line_bytes" && e.field().ends_with(".line_bytes")))
                culprit = p;
        throw InputError(source, culprit->field,
                         culprit->path == e.field() ? e.message() : e.field() + ": " + e.message());
    }
}

nlohmann::json memoryConfigJson(const MemoryConfig& memory) {
    return memoryJson(memory, true);
}

const char* memoryOrderName(MemoryOrder o) {
    return o == MemoryOrder::Patches ? "patches" : "regions";
}

const char* cacheClientName(CacheClient c) {
    switch (c) {
        case CacheClient::Depth:
            return "depth";
        case CacheClient::Visibility:
            return "visibility";
        case CacheClient::VertexInput:
            return "vertex_input";
        case CacheClient::Layers:
            return "layers";
        case CacheClient::Image:
            return "image";
        case CacheClient::LastLevel:
            return "llc";
    }
    return "?";
}

const char* cacheClientTitle(CacheClient c) {
    switch (c) {
        case CacheClient::Depth:
            return "depth cache";
        case CacheClient::Visibility:
            return "visibility cache";
        case CacheClient::VertexInput:
            return "vertex input cache";
        case CacheClient::Layers:
            return "layer cache";
        case CacheClient::Image:
            return "image cache";
        case CacheClient::LastLevel:
            return "last-level cache";
    }
    return "?";
}

HardwareConfig parseHardwareConfig(std::string_view text, const std::string& path) {
    const Json json = parseJson(text, path);
    HardwareConfig config;
    ObjectReader root(json, "", path);
    if (const Json* j = root.find("clock_ghz"))
        config.clockGHz = checked(*j, kClock, path, "clock_ghz");
    if (const Json* j = root.find("scratch_budget_bytes"))
        config.scratchBudgetBytes =
            std::uint64_t(checked(*j, kScratch, path, "scratch_budget_bytes"));
    auto stages = root.object("stages");
    if (!stages) root.fail("stages", "missing the per-stage configuration");
    for (int s = 0; s < kStageCount; ++s) {
        auto stage = stages->object(stageName(Stage(s)));
        if (!stage) stages->fail(stages->fieldName(stageName(Stage(s))), "missing stage");
        readStage(*stage, config.stages[std::size_t(s)], Stage(s));
    }
    stages->finish();
    if (auto memory = root.object("memory")) config.memory = readMemory(*memory);
    if (auto energy = root.object("energy")) config.energy = readEnergyTable(*energy);
    root.finish();
    return config;
}

HardwareConfig readHardwareConfig(const std::string& path) {
    return parseHardwareConfig(readTextFile(path), path);
}

HardwareConfig defaultHardwareConfig() {
    const auto text = builtinAsset("hw/default.json");
    if (!text) throw InputError("builtin:hw/default.json", "", "missing from the build");
    return parseHardwareConfig(*text, "builtin:hw/default.json");
}

void setHardwareParameter(HardwareConfig& c, const std::string& path, const Json& value,
                          const std::string& source, const std::string& field) {
    auto fail = [&](const std::string& why) { throw InputError(source, field, why); };
    if (path == "clock_ghz") {
        c.clockGHz = checked(value, kClock, source, field);
        return;
    }
    if (path == "scratch_budget_bytes") {
        c.scratchBudgetBytes = std::uint64_t(checked(value, kScratch, source, field));
        return;
    }
    if (path.starts_with("memory."))
        return setHardwareParameters(c, {{path, value, field}}, source);
    if (path.starts_with("energy."))
        return setEnergyEntry(c.energy, path.substr(7), value, source, field);
    const auto dot = path.find('.');
    if (dot == std::string::npos) fail("unknown hardware parameter '" + path + "'");
    const std::string stageText = path.substr(0, dot), rest = path.substr(dot + 1);
    int stage = -1;
    for (int s = 0; s < kStageCount; ++s)
        if (stageText == stageName(Stage(s))) stage = s;
    if (stage < 0) fail("unknown stage '" + stageText + "'");
    StageConfig& s = c.stages[std::size_t(stage)];
    if (rest == "units")
        s.units = int(checked(value, kUnits, source, field));
    else if (rest == "latency")
        s.latency = checked(value, kLatency, source, field);
    else if (rest == "fifo_depth")
        s.fifoDepth = int(checked(value, kFifoDepth, source, field));
    else if (rest.starts_with("throughput.")) {
        const int op = findOp(rest.substr(11), Stage(stage));
        if (op < 0) fail("stage " + stageText + " has no operation '" + rest.substr(11) + "'");
        s.throughput[std::size_t(op)] = checked(value, kThroughput, source, field);
    } else {
        fail("unknown hardware parameter '" + path + "'");
    }
}

}  // namespace patchsim
