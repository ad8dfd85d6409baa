#include "backend/images/image_io_module.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "backend/images/image.h"
#include "core/counters.h"
#include "core/parallel.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

const Counter loadTestItems{"Test/Image module load items", "items",
                            "Counted by the image module test only"};

bool mapped(const std::string& library) {
    std::ifstream maps("/proc/self/maps");
    std::string line;
    while (std::getline(maps, line))
        if (line.find(library) != std::string::npos) return true;
    return false;
}

// ctest runs each test in its own process, where this checks what a user's process does: a command
// that writes no image never binds OpenImageIO's libraries.
TEST(ImageIoModule, OpenImageIOIsBoundOnlyWhenAnImageIsNeeded) {
    if (mapped("libpatchsim_image_io"))
        GTEST_SKIP() << "an earlier test in this process loaded the module";
    EXPECT_FALSE(mapped("libOpenImageIO")) << "bound at start-up, without the module";
    EXPECT_EQ(imageIo().version, kImageIoVersion);
    EXPECT_TRUE(mapped("libpatchsim_image_io"));
    EXPECT_TRUE(mapped("libOpenImageIO"));
}

// The load runs beside the work: workers started before it count, and a loop's totals are exact.
TEST(ImageIoModule, WorkersRunAndCountWhileTheModuleLoads) {
    WorkerPool::shared().startHelpers(1);
    preloadImageIo();
    CounterRegistry::instance().reset();
    parallelFor(1000, 2, [](int, std::size_t) { ++loadTestItems; });
    EXPECT_EQ(CounterRegistry::instance().snapshot()[loadTestItems], 1000);
    EXPECT_EQ(imageIo().version, kImageIoVersion);
}

TEST(ImageIoModule, NamedFloatChannelsRoundTripThroughTheModule) {
    const std::string path = test::temporaryDirectory() + "/channels.exr";
    const std::vector<float> pixels = {0.25f, 2.0f, -1.0f, 7.5f, 1e-3f, 3.0f};
    writeFloatChannels(path, 3, 1, {"Z", "coverage"}, pixels);
    EXPECT_EQ(readChannelNames(path), (std::vector<std::string>{"Z", "coverage"}));
    EXPECT_EQ(readChannel(path, "coverage"), (std::vector<float>{2.0f, 7.5f, 3.0f}));
    EXPECT_EQ(readChannel(path, "Z"), (std::vector<float>{0.25f, -1.0f, 1e-3f}));
}

}  // namespace
}  // namespace patchsim
