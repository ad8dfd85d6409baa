#include "rasterizer/common/transparent_layers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace patchsim {
namespace {

LayerFragment fragment(float depth, int patch, int object) {
    return {{depth, patch, 0, 0, 0}, object};
}

std::vector<float> depths(const TransparentLayers& l, std::size_t sample) {
    std::vector<float> d;
    for (int i = 0; i < l.count(sample); ++i) d.push_back(l.layers(sample)[i].record.depth);
    std::sort(d.begin(), d.end());
    return d;
}

TEST(TransparentLayers, KeepsTheNearestWhateverTheOrderAndCountsOverflow) {
    std::vector<LayerFragment> all;
    for (int i = 0; i < 10; ++i) all.push_back(fragment(float(i + 1), i, i));
    std::mt19937 rng(5);
    for (int trial = 0; trial < 20; ++trial) {
        std::shuffle(all.begin(), all.end(), rng);
        TransparentLayers layers(4, 3);
        int dropped = 0;
        for (const LayerFragment& f : all) dropped += !layers.offer(2, trial % layers.pools(), f);
        EXPECT_EQ(dropped, 7);
        EXPECT_EQ(depths(layers, 2), (std::vector<float>{1, 2, 3}));
        EXPECT_EQ(layers.count(0), 0);
        EXPECT_EQ(layers.layers(0), nullptr);
    }
}

TEST(TransparentLayers, OneSurfaceSeenTwiceThroughASharedEdgeIsOneFragment) {
    TransparentLayers layers(1, 4);
    EXPECT_TRUE(layers.offer(0, 0, fragment(2.0f, 7, 1)));
    EXPECT_TRUE(layers.offer(0, 0, fragment(2.0000009f, 3, 1)));  // same object, within 1e-6
    ASSERT_EQ(layers.count(0), 1);
    EXPECT_EQ(layers.layers(0)[0].record.patch, 7);         // the nearer one stays
    EXPECT_TRUE(layers.offer(0, 0, fragment(2.0f, 5, 1)));  // equal depth: the lower patch wins
    ASSERT_EQ(layers.count(0), 1);
    EXPECT_EQ(layers.layers(0)[0].record.patch, 5);
    EXPECT_TRUE(layers.offer(0, 0, fragment(2.0f, 9, 2)));  // another object at that depth stays
    EXPECT_EQ(layers.count(0), 2);
}

TEST(TransparentLayers, SamplesInDifferentPoolsAreIndependent) {
    TransparentLayers layers(3, 2);
    layers.offer(0, 0, fragment(1, 0, 0));
    layers.offer(1, 5, fragment(2, 1, 1));
    layers.offer(2, 0, fragment(3, 2, 2));
    EXPECT_EQ(layers.layers(0)[0].record.depth, 1.0f);
    EXPECT_EQ(layers.layers(1)[0].record.depth, 2.0f);
    EXPECT_EQ(layers.layers(2)[0].record.depth, 3.0f);
}

}  // namespace
}  // namespace patchsim
