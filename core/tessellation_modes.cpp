#include "core/tessellation_modes.h"

#include "core/enum_names.h"

namespace patchsim {

namespace {

constexpr EnumName<Partitioning> kPartitionings[] = {
    {Partitioning::Integer, "integer"},
    {Partitioning::Pow2, "pow2"},
    {Partitioning::FractionalOdd, "fractional_odd"},
    {Partitioning::FractionalEven, "fractional_even"}};
constexpr EnumName<InsideReduction> kInsideReductions[] = {{InsideReduction::Min, "min"},
                                                           {InsideReduction::Max, "max"},
                                                           {InsideReduction::Average, "average"}};

}  // namespace

const char* partitioningName(Partitioning p) {
    return nameIn(kPartitionings, p);
}
bool parsePartitioning(std::string_view name, Partitioning& out) {
    return parseIn(kPartitionings, name, out);
}

const char* insideReductionName(InsideReduction r) {
    return nameIn(kInsideReductions, r);
}
bool parseInsideReduction(std::string_view name, InsideReduction& out) {
    return parseIn(kInsideReductions, name, out);
}

}  // namespace patchsim
