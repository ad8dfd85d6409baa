#pragma once
// Names of the tessellation modes a scene can choose; the tessellator implements them.

#include <cstdint>
#include <string_view>

namespace patchsim {

enum class Partitioning : std::uint8_t { Integer, Pow2, FractionalOdd, FractionalEven };
enum class InsideReduction : std::uint8_t { Min, Max, Average };

const char* partitioningName(Partitioning p);
// Returns false when the name is not one of integer, pow2, fractional_odd, fractional_even.
bool parsePartitioning(std::string_view name, Partitioning& out);

const char* insideReductionName(InsideReduction r);
// Returns false when the name is not one of min, max, average.
bool parseInsideReduction(std::string_view name, InsideReduction& out);

}  // namespace patchsim
