#include "rasterizer/raster_work.h"

#include <algorithm>

namespace patchsim {

namespace {

#define PATCHSIM_RASTER_COUNTER(field, name, unit, kind, definition) \
    const Counter field##Counter{name, unit, definition, CounterKind::kind};
PATCHSIM_RASTER_WORK(PATCHSIM_RASTER_COUNTER)
#undef PATCHSIM_RASTER_COUNTER

constexpr bool isMax(CounterKind kind) {
    return kind == CounterKind::Max;
}

}  // namespace

void RasterWork::add(const RasterWork& o) {
#define PATCHSIM_RASTER_ADD(field, name, unit, kind, definition) \
    field = isMax(CounterKind::kind) ? std::max(field, o.field) : field + o.field;
    PATCHSIM_RASTER_WORK(PATCHSIM_RASTER_ADD)
#undef PATCHSIM_RASTER_ADD
}

void RasterWork::flush() const {
#define PATCHSIM_RASTER_FLUSH(field, name, unit, kind, definition) \
    if (isMax(CounterKind::kind))                                  \
        field##Counter.raiseTo(field);                             \
    else                                                           \
        field##Counter += field;
    PATCHSIM_RASTER_WORK(PATCHSIM_RASTER_FLUSH)
#undef PATCHSIM_RASTER_FLUSH
}

const RasterCounters& rasterCounters() {
#define PATCHSIM_RASTER_REF(field, name, unit, kind, definition) field##Counter,
    static const RasterCounters counters{PATCHSIM_RASTER_WORK(PATCHSIM_RASTER_REF)};
#undef PATCHSIM_RASTER_REF
    return counters;
}

const RatioCounter& sampleTestEfficiency() {
    static const RatioCounter ratio{"RS/Sample test efficiency",
                                    "Visibility samples per sample tested (DESIGN.md section 8)",
                                    visibilitySamplesCounter, samplesTestedCounter};
    return ratio;
}

}  // namespace patchsim
