// The vector sampler (sample_kernel.h), compiled once per SIMD target (Highway's foreach_target
// re-includes this file).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/sample_kernel.cpp"
#include "core/sample_kernel.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>

#include "core/samples.h"

HWY_BEFORE_NAMESPACE();
namespace patchsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// 64-bit lanes for the hashes; 32-bit integer and float lanes of the same count beside them.
using D64 = hn::ScalableTag<std::uint64_t>;
using D32 = hn::Rebind<std::uint32_t, D64>;
using DI32 = hn::Rebind<std::int32_t, D64>;
using DF = hn::Rebind<float, D64>;
using V64 = hn::Vec<D64>;
using V32 = hn::Vec<D32>;
using VF = hn::Vec<DF>;

constexpr std::size_t kMaxSampleLanes = hn::MaxLanes(D64{});
alignas(64) constexpr std::uint32_t kLaneNumbers[16] = {0, 1, 2,  3,  4,  5,  6,  7,
                                                        8, 9, 10, 11, 12, 13, 14, 15};
static_assert(kMaxSampleLanes <= 16);

// mix64 (samples.cpp), lane by lane.
HWY_INLINE V64 mixLanes(V64 x) {
    const D64 d;
    x = hn::Add(x, hn::Set(d, 0x9e3779b97f4a7c15ull));
    x = hn::Mul(hn::Xor(x, hn::ShiftRight<30>(x)), hn::Set(d, 0xbf58476d1ce4e5b9ull));
    x = hn::Mul(hn::Xor(x, hn::ShiftRight<27>(x)), hn::Set(d, 0x94d049bb133111ebull));
    return hn::Xor(x, hn::ShiftRight<31>(x));
}

// Unsigned a < b for 32-bit lanes (sums of hash keys reach 2^32): compared as signed after
// flipping the top bit.
HWY_INLINE hn::Mask<D32> lessUnsignedLanes(V32 a, V32 b) {
    const D32 d;
    const DI32 di;
    const V32 top = hn::Set(d, 0x80000000u);
    return hn::RebindMask(
        d, hn::Lt(hn::BitCast(di, hn::Xor(a, top)), hn::BitCast(di, hn::Xor(b, top))));
}

class PixelKernel {
  public:
    PixelKernel(const PixelSampleRecipe& recipe, const std::uint64_t* streams)
        : recipe_(recipe), streams_(streams), count_(recipe.count) {}

    // Samples [first, first + lanes) of the pixel, into the lanes of `out`.
    void make(std::uint32_t first, VF out[5]) const {
        const V32 index = indices(first);
        const V64 index64 = hn::PromoteTo(d64_, index);
        const float n = float(recipe_.count);
        if (recipe_.gridSide > 0) {
            const V32 cell = permute(index, std::uint32_t(streams_[1]));
            // Exact: cell < 4096 and side <= 64, so the rounded quotient is never an integer
            // too high (the test covers every square count).
            const VF side = hn::Set(df_, float(recipe_.gridSide));
            const VF cellF = toFloat(cell);
            const VF row = hn::Floor(hn::Div(cellF, side));
            const VF column = hn::Sub(cellF, hn::Mul(row, side));
            out[0] = hn::Div(hn::Add(column, jitter(2, index64)), side);
            out[1] = hn::Div(hn::Add(row, jitter(3, index64)), side);
        } else {
            out[0] = hn::Div(hn::Add(stratum(4, index), jitter(2, index64)), hn::Set(df_, n));
            out[1] = hn::Div(hn::Add(stratum(5, index), jitter(3, index64)), hn::Set(df_, n));
        }
        const VF spread = hn::Set(df_, recipe_.spread);
        out[2] = recipe_.timeSamples
                     ? hn::Div(hn::Add(stratum(6, index), jitter(7, index64)), spread)
                     : hn::Set(df_, recipe_.stillTime);
        if (recipe_.lensSamples) {
            out[3] = hn::Div(hn::Add(stratum(8, index), jitter(9, index64)), spread);
            out[4] = hn::Div(hn::Add(stratum(10, index), jitter(11, index64)), spread);
        } else {
            out[3] = out[4] = hn::Set(df_, 0.5f);
        }
        // Guard against rounding up to 1 in the divisions above.
        const VF belowOne = hn::Set(df_, 0.99999994f), one = hn::Set(df_, 1.0f);
        for (int k = 0; k < 2; ++k) out[k] = hn::Min(out[k], belowOne);
        for (int k = 2; k < 5; ++k) out[k] = hn::Min(out[k], one);
    }

    // SampleGenerator::permute: Kensler's hash permutation, walked again in the lanes whose
    // value falls outside [0, n) until none does, then offset by the key.
    V32 permute(V32 i, std::uint32_t key) const {
        const V32 n = hn::Set(d32_, recipe_.count);
        V32 value = i;
        auto walking = hn::FirstN(d32_, hn::Lanes(d32_));
        do {
            value = hn::IfThenElse(walking, round(value, key), value);
            walking = hn::And(walking, hn::Not(lessUnsignedLanes(value, n)));
        } while (!hn::AllFalse(d32_, walking));
        // (value + key) mod n, with value < n: a sum that wraps is below n already; one that
        // does not is congruent to value + (key mod n), which is below 2n.
        const V32 sum = hn::Add(value, hn::Set(d32_, key));
        V32 reduced = hn::Add(value, hn::Set(d32_, count_.remainder(key)));
        reduced = hn::IfThenElse(lessUnsignedLanes(reduced, n), reduced, hn::Sub(reduced, n));
        return hn::IfThenElse(lessUnsignedLanes(sum, hn::Set(d32_, key)), sum, reduced);
    }

    // Indices [first, first + lanes), those past the last sample as 0: a permutation walked
    // from outside [0, n) may never come back into it.
    V32 indices(std::uint32_t first) const {
        return hn::IfThenElseZero(hn::FirstN(d32_, recipe_.count - first),
                                  hn::Add(laneNumbers_, hn::Set(d32_, first)));
    }

  private:
    // Integers below 2^24 (strata, cells), exactly.
    VF toFloat(V32 v) const { return hn::ConvertTo(df_, hn::BitCast(di32_, v)); }

    VF jitter(int dimension, V64 index64) const {
        if (!recipe_.jitter) return hn::Zero(df_);
        const V64 bits = hn::ShiftRight<40>(
            mixLanes(hn::Xor(hn::Set(d64_, streams_[dimension]), index64)));  // 24 random bits
        return hn::Mul(toFloat(hn::TruncateTo(d32_, bits)), hn::Set(df_, 1.0f / 16777216.0f));
    }

    VF stratum(int dimension, V32 index) const {
        return toFloat(permute(index, std::uint32_t(streams_[dimension] >> 32)));
    }

    V32 round(V32 i, std::uint32_t key) const {
        const V32 w = hn::Set(d32_, recipe_.permutationMask);
        auto constant = [&](std::uint32_t c) { return hn::Set(d32_, c); };
        i = hn::Xor(i, constant(key));
        i = hn::Mul(i, constant(0xe170893d));
        i = hn::Xor(i, constant(key >> 16));
        i = hn::Xor(i, hn::ShiftRight<4>(hn::And(i, w)));
        i = hn::Xor(i, constant(key >> 8));
        i = hn::Mul(i, constant(0x0929eb3f));
        i = hn::Xor(i, constant(key >> 23));
        i = hn::Xor(i, hn::ShiftRight<1>(hn::And(i, w)));
        i = hn::Mul(i, constant(1 | key >> 27));
        i = hn::Mul(i, constant(0x6935fa69));
        i = hn::Xor(i, hn::ShiftRight<11>(hn::And(i, w)));
        i = hn::Mul(i, constant(0x74dcb303));
        i = hn::Xor(i, hn::ShiftRight<2>(hn::And(i, w)));
        i = hn::Mul(i, constant(0x9e501cc3));
        i = hn::Xor(i, hn::ShiftRight<2>(hn::And(i, w)));
        i = hn::Mul(i, constant(0xc860a3df));
        i = hn::And(i, w);
        return hn::Xor(i, hn::ShiftRight<5>(i));
    }

    const D64 d64_{};
    const D32 d32_{};
    const DI32 di32_{};
    const DF df_{};
    const PixelSampleRecipe& recipe_;
    const std::uint64_t* streams_;
    FixedDivisor count_;
    // 0, 1, 2, ... loaded from a constant: Highway's Iota stores the lanes one by one and loads
    // them back as a vector, which the store buffer cannot forward.
    const V32 laneNumbers_ = hn::Load(d32_, kLaneNumbers);
};

void MakePixelSamplesImpl(const PixelSampleRecipe& recipe, const std::uint64_t* streams,
                          Sample* out) {
    const PixelKernel kernel(recipe, streams);
    const DF df;
    const std::uint32_t lanes = std::uint32_t(hn::Lanes(df));
    alignas(64) float values[5][kMaxSampleLanes];
    for (std::uint32_t first = 0; first < recipe.count; first += lanes) {
        VF v[5];
        kernel.make(first, v);
        for (int k = 0; k < 5; ++k) hn::Store(v[k], df, values[k]);
        const std::uint32_t made = std::min(lanes, recipe.count - first);
        for (std::uint32_t lane = 0; lane < made; ++lane) {
            Sample& s = out[first + lane];
            s.pixelOffset = {values[0][lane], values[1][lane]};
            s.time = values[2][lane];
            s.lens = {values[3][lane], values[4][lane]};
        }
    }
}

void PermuteIndicesImpl(const PixelSampleRecipe& recipe, std::uint32_t key, std::uint32_t* out) {
    const PixelKernel kernel(recipe, nullptr);
    const D32 d32;
    const std::uint32_t lanes = std::uint32_t(hn::Lanes(d32));
    alignas(64) std::uint32_t values[kMaxSampleLanes];
    for (std::uint32_t first = 0; first < recipe.count; first += lanes) {
        hn::Store(kernel.permute(kernel.indices(first), key), d32, values);
        std::copy_n(values, std::min(lanes, recipe.count - first), out + first);
    }
}

const char* SampleKernelTargetImpl() {
    return hwy::TargetName(HWY_TARGET);
}

}  // namespace HWY_NAMESPACE
}  // namespace patchsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace patchsim {

HWY_EXPORT(MakePixelSamplesImpl);
HWY_EXPORT(PermuteIndicesImpl);
HWY_EXPORT(SampleKernelTargetImpl);

void makePixelSamples(const PixelSampleRecipe& recipe, const std::uint64_t* streams, Sample* out) {
    HWY_DYNAMIC_DISPATCH(MakePixelSamplesImpl)(recipe, streams, out);
}

void permuteIndices(const PixelSampleRecipe& recipe, std::uint32_t key, std::uint32_t* out) {
    HWY_DYNAMIC_DISPATCH(PermuteIndicesImpl)(recipe, key, out);
}

const char* sampleKernelTarget() {
    return HWY_DYNAMIC_DISPATCH(SampleKernelTargetImpl)();
}

}  // namespace patchsim
#endif
