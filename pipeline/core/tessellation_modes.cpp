#include "pipeline/core/tessellation_modes.h"

namespace patchsim {

const char* partitioningName(Partitioning p) {
    switch (p) {
        case Partitioning::Integer:
            return "integer";
        case Partitioning::Pow2:
            return "pow2";
        case Partitioning::FractionalOdd:
            return "fractional_odd";
        case Partitioning::FractionalEven:
            return "fractional_even";
    }
    return "?";
}

bool parsePartitioning(std::string_view name, Partitioning& out) {
    for (Partitioning p : {Partitioning::Integer, Partitioning::Pow2, Partitioning::FractionalOdd,
                           Partitioning::FractionalEven}) {
        if (name == partitioningName(p)) {
            out = p;
            return true;
        }
    }
    return false;
}

const char* insideReductionName(InsideReduction r) {
    switch (r) {
        case InsideReduction::Min:
            return "min";
        case InsideReduction::Max:
            return "max";
        case InsideReduction::Average:
            return "average";
    }
    return "?";
}

bool parseInsideReduction(std::string_view name, InsideReduction& out) {
    for (InsideReduction r :
         {InsideReduction::Min, InsideReduction::Max, InsideReduction::Average}) {
        if (name == insideReductionName(r)) {
            out = r;
            return true;
        }
    }
    return false;
}

}  // namespace patchsim
