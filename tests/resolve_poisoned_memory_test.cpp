// The resolve's output planes start unwritten (default_init_allocator.h): the workers' writes are
// their first touch. This test program replaces the global operator new so that every allocation
// starts as NaNs, and checks that a frame's image and AOVs hold none: a pixel that a filter or an
// AOV left unwritten would keep its NaN, where a fresh page of zeros would hide it. Each render
// starts with the frame memory cache emptied (frame_memory.h), so that its planes are fresh
// allocations and not the last render's planes, whose values would hide an unwritten pixel too.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "backend/images/image.h"
#include "core/frame_memory.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "tests/test_paths.h"

namespace {

constexpr unsigned char kPoisonByte = 0xFF;  // every float made of it is a NaN

void* poisoned(void* p, std::size_t size) {
    if (!p) throw std::bad_alloc();
    std::memset(p, kPoisonByte, size);
    return p;
}

void* allocateAligned(std::size_t size, std::align_val_t alignment) {
    const auto a = std::max(static_cast<std::size_t>(alignment), sizeof(void*));
    return std::aligned_alloc(a, (std::max<std::size_t>(size, 1) + a - 1) / a * a);
}

}  // namespace

void* operator new(std::size_t size) {
    return poisoned(std::malloc(std::max<std::size_t>(size, 1)), size);
}
void* operator new[](std::size_t size) {
    return poisoned(std::malloc(std::max<std::size_t>(size, 1)), size);
}
void* operator new(std::size_t size, std::align_val_t alignment) {
    return poisoned(allocateAligned(size, alignment), size);
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
    return poisoned(allocateAligned(size, alignment), size);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
    std::free(p);
}

namespace patchsim {
namespace {

bool allFinite(const FloatPlane& plane) {
    return std::all_of(plane.begin(), plane.end(), [](float v) { return std::isfinite(v); });
}

// The poison is there: an unwritten plane is all NaNs, and a value-filled one is not.
TEST(PoisonedMemory, UnwrittenPlanesAreNaNsAndFilledOnesAreNot) {
    const FloatPlane unwritten(64);
    EXPECT_TRUE(
        std::all_of(unwritten.begin(), unwritten.end(), [](float v) { return std::isnan(v); }));
    EXPECT_TRUE(allFinite(FloatPlane(64, 0.5f)));
    EXPECT_TRUE(allFinite(Image(8, 4).rgb));
    EXPECT_FALSE(allFinite(Image::unfilled(8, 4).rgb));
}

// Both filters, one thread and two, both shading rates, with transparent layers and motion:
// every pixel of the image and of the four AOVs is written.
TEST(PoisonedMemory, ResolveWritesEveryPixelOfTheImageAndAovs) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/transparency.json"));
    scene.film = {40, 30, 4, 5};
    scene.objects[0].close.translate += Vec3(0.5f, 0.0f, 0.0f);
    for (ResolveFilter filter : {ResolveFilter::Box, ResolveFilter::Gaussian})
        for (ShadingRate rate : {ShadingRate::PerFragment, ShadingRate::PerPixelPrimitive})
            for (int threads : {1, 2}) {
                RenderOptions options;
                options.threads = threads;
                options.resolve.filter = filter;
                options.resolve.shadingRate = rate;
                releaseCachedFrameMemory();
                const ResolvedFrame f = renderScene(scene, options).frame;
                const std::size_t pixels = std::size_t(scene.film.width * scene.film.height);
                ASSERT_EQ(f.color.rgb.size(), 3 * pixels);
                EXPECT_TRUE(allFinite(f.color.rgb));
                for (const FloatPlane* aov : {&f.depth, &f.coverage, &f.motionX, &f.motionY}) {
                    ASSERT_EQ(aov->size(), pixels);
                    EXPECT_TRUE(allFinite(*aov));
                }
                // Some pixels see only the background: their depth and motion are written as 0.
                std::size_t empty = 0;
                for (std::size_t p = 0; p < pixels; ++p) {
                    if (f.coverage[p] != 0.0f) continue;
                    ++empty;
                    EXPECT_EQ(f.depth[p], 0.0f);
                    EXPECT_EQ(f.motionX[p], 0.0f);
                }
                EXPECT_GT(empty, 0u);
            }
}

}  // namespace
}  // namespace patchsim
