#include "core/frame_memory.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "backend/images/image.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/common/visibility_buffer.h"
#include "tests/test_paths.h"

#if defined(__linux__)
#include <sys/resource.h>
#endif

namespace patchsim {
namespace {

std::uintptr_t address(const void* p) {
    return reinterpret_cast<std::uintptr_t>(p);
}

TEST(FrameMemory, SmallBuffersAreCacheLineAlignedAndUsable) {
    for (const std::size_t bytes : {std::size_t(0), std::size_t(1), std::size_t(4096)}) {
        const auto memory = allocateFrameMemory(bytes);
        ASSERT_NE(memory, nullptr);
        EXPECT_EQ(address(memory.get()) % 64, 0u) << bytes << " bytes";
        EXPECT_FALSE(frameMemoryAdvisesHugePages(bytes));
        std::memset(memory.get(), 0xab, bytes == 0 ? 1 : bytes);
    }
}

TEST(FrameMemory, LargeBuffersStartOnAHugePageWhereHugePagesAreAdvised) {
    const std::size_t bytes = 3 * kHugePageBytes + 17;
    const auto memory = allocateFrameMemory(bytes);
    ASSERT_NE(memory, nullptr);
    const std::size_t alignment = frameMemoryAdvisesHugePages(bytes) ? kHugePageBytes : 64;
    EXPECT_EQ(address(memory.get()) % alignment, 0u);
    auto* bytesView = static_cast<unsigned char*>(memory.get());
    bytesView[0] = 1;
    bytesView[bytes - 1] = 2;
    EXPECT_EQ(bytesView[0] + bytesView[bytes - 1], 3);
}

#if defined(__linux__)
long minorFaults() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt;
}

// What the huge pages are for: first touching a frame's buffer should not cost a fault per 4 KiB.
TEST(FrameMemory, FirstTouchOfALargeBufferFaultsOncePerHugePageNotPerSmallPage) {
    constexpr std::size_t kBytes = std::size_t(64) << 20;
    if (!frameMemoryAdvisesHugePages(kBytes))
        GTEST_SKIP() << "transparent huge pages are switched off on this host";
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer's shadow memory takes page faults of its own";
#endif
    const auto memory = allocateFrameMemory(kBytes);
    const long before = minorFaults();
    std::memset(memory.get(), 0, kBytes);
    const long faults = minorFaults() - before;
    constexpr long kSmallPages = long(kBytes / 4096);
    // 32 huge pages; allow the kernel to fall back to small pages for a quarter of the buffer
    // (fragmented memory) before calling the advice ineffective.
    RecordProperty("faults", int(faults));
    EXPECT_LT(faults, kSmallPages / 4) << faults << " faults for " << kSmallPages << " small pages";
}

// An output plane of the default film (320x240 floats, 300 KiB) is an eighth of a huge page or
// more: its first touch faults once per huge page too, not 75 times.
TEST(FrameMemory, AnOutputPlaneOfTheDefaultFilmFaultsOncePerHugePage) {
    constexpr std::size_t kPixels = 320 * 240;
    if (!frameMemoryAdvisesHugePages(kPixels * sizeof(float)))
        GTEST_SKIP() << "transparent huge pages are switched off on this host";
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer's shadow memory takes page faults of its own";
#endif
    releaseCachedFrameMemory();
    FloatPlane plane(kPixels);
    EXPECT_EQ(address(plane.data()) % kHugePageBytes, 0u);
    const long before = minorFaults();
    std::fill(plane.begin(), plane.end(), 1.0f);
    const long faults = minorFaults() - before;
    RecordProperty("faults", int(faults));
    EXPECT_LT(faults, long(kPixels * sizeof(float) / 4096 / 4)) << faults << " faults";
}

// The point of the cache: a frame after the first reuses the first one's buffers, so it finds
// them faulted and zeroed already. Its page faults are counted over a whole render of the default
// scene: before the cache and the planes' huge pages, the output planes alone took about 530 a
// frame, and without huge pages the visibility buffer 9,600 (a fault per small page). With the
// cache the second frame takes about 40 (huge pages) or 120 (small pages) on a quiet machine, and
// up to about 250 when another process keeps the second core busy: the rest of the frame's memory
// comes from malloc's per-thread arenas, and which thread allocates what follows the schedule.
// So the bound is a tenth of the visibility buffer's small pages, which fails without the cache.
TEST(FrameMemory, AFrameAfterTheFirstReusesItsBuffersAndTakesFewPageFaults) {
    const SceneDesc scene = readSceneFile(test::sourcePath("scenes/default.json"));
    RenderOptions options;
    options.threads = 2;
    releaseCachedFrameMemory();
    const std::size_t bufferBytes = renderScene(scene, options).visibility->records().size_bytes();
    EXPECT_GT(cachedFrameMemoryBytes(), bufferBytes);  // the buffer and the output planes
    const long before = minorFaults();
    const RenderResult second = renderScene(scene, options);
    const long faults = minorFaults() - before;
    EXPECT_EQ(cachedFrameMemoryBytes(), 0u);  // every block taken back
    RecordProperty("faults", int(faults));
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer's shadow memory takes page faults of its own";
#endif
    const long bound = long(bufferBytes / 4096 / 10);
    EXPECT_LT(faults, bound) << faults << " faults in the second frame";
}
#endif

// A frame-sized block given back is kept, and the next request of its size takes it back; small
// blocks are not kept.
TEST(FrameMemory, ABlockGivenBackIsTakenByTheNextRequestOfItsSize) {
    releaseCachedFrameMemory();
    const std::size_t bytes = kSmallestHugePageBuffer + 1000;
    void* first = allocateFrameBytes(bytes);
    releaseFrameBytes(first, bytes);
    EXPECT_GE(cachedFrameMemoryBytes(), bytes);
    void* again = allocateFrameBytes(bytes);
    EXPECT_EQ(again, first);
    EXPECT_EQ(cachedFrameMemoryBytes(), 0u);
    releaseFrameBytes(again, bytes);

    void* small = allocateFrameBytes(4096);
    releaseFrameBytes(small, 4096);
    EXPECT_GE(cachedFrameMemoryBytes(), bytes);  // the large block, not the small one
    releaseCachedFrameMemory();
    EXPECT_EQ(cachedFrameMemoryBytes(), 0u);
}

// A frame of another shape does not keep the last one's blocks beside its own: a request the cache
// cannot serve gives every cached block back first.
TEST(FrameMemory, ARequestOfAnotherSizeGivesTheCachedBlocksBack) {
    releaseCachedFrameMemory();
    const std::size_t bytes = 3 * kHugePageBytes;
    {
        const auto a = allocateFrameMemory(bytes);
        const auto b = allocateFrameMemory(bytes);
    }
    EXPECT_EQ(cachedFrameMemoryBytes(), 2 * bytes);
    const auto other = allocateFrameMemory(5 * kHugePageBytes);
    EXPECT_EQ(cachedFrameMemoryBytes(), 0u);
    const auto again = allocateFrameMemory(bytes);  // fresh memory now, and still usable
    std::memset(again.get(), 0, bytes);
}

// Run by the ctest entry FrameMemoryWithHugePagesOff, which sets PATCHSIM_HUGE_PAGES=off.
TEST(FrameMemory, TheEnvironmentSwitchesHugePagesOff) {
    const char* choice = std::getenv("PATCHSIM_HUGE_PAGES");
    if (!choice || std::string(choice) != "off")
        GTEST_SKIP() << "runs with PATCHSIM_HUGE_PAGES=off (ctest: FrameMemoryWithHugePagesOff)";
    EXPECT_FALSE(frameMemoryAdvisesHugePages(std::size_t(64) << 20));
    const auto memory = allocateFrameMemory(std::size_t(3) << 20);
    EXPECT_EQ(address(memory.get()) % 64, 0u);
}

TEST(FrameMemory, TheVisibilityBufferStartsEmptyInFrameMemory) {
    const VisibilityBuffer buffer(97, 61, 9, 100.0f, 2);  // 1.7 MB: not a whole number of chunks
    ASSERT_EQ(buffer.records().size(), std::size_t(97 * 61 * 9));
    EXPECT_EQ(address(buffer.records().data()) % 64, 0u);
    for (const VisibilityRecord& r : buffer.records()) {
        ASSERT_FALSE(r.hit());
        ASSERT_EQ(r.depth, std::numeric_limits<float>::infinity());
    }
    const VisibilityBuffer large(320, 240, 16, 100.0f, 2);  // 39 MB: the default film
    EXPECT_EQ(address(large.records().data()) %
                  (frameMemoryAdvisesHugePages(large.records().size_bytes()) ? kHugePageBytes : 64),
              0u);
    for (const VisibilityRecord& r : large.records()) ASSERT_FALSE(r.hit());
    EXPECT_EQ(large.depthBound(319, 239, 15), 100.0f);
}

}  // namespace
}  // namespace patchsim
