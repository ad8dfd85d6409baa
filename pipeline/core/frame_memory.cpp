#include "pipeline/core/frame_memory.h"

#include <cstdlib>
#include <fstream>
#include <new>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace patchsim {
namespace {

constexpr std::size_t kCacheLineBytes = 64;

std::size_t roundUp(std::size_t bytes, std::size_t multiple) {
    return (bytes + multiple - 1) / multiple * multiple;
}

// Transparent huge pages are on unless the kernel says "[never]" (or has no such setting), or the
// user switched them off with PATCHSIM_HUGE_PAGES=off (on a host whose memory is fragmented, the
// kernel compacts memory to find huge pages, and that can cost more than the faults it saves).
bool hugePagesWanted() {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    static const bool wanted = [] {
        const char* choice = std::getenv("PATCHSIM_HUGE_PAGES");
        if (choice && std::string(choice) == "off") return false;
        std::ifstream setting("/sys/kernel/mm/transparent_hugepage/enabled");
        std::string modes;
        if (!std::getline(setting, modes)) return false;
        return modes.find("[never]") == std::string::npos;
    }();
    return wanted;
#else
    return false;
#endif
}

}  // namespace

void FrameMemoryRelease::operator()(void* p) const {
    std::free(p);
}

bool frameMemoryAdvisesHugePages(std::size_t bytes) {
    return bytes >= kHugePageBytes && hugePagesWanted();
}

std::unique_ptr<void, FrameMemoryRelease> allocateFrameMemory(std::size_t bytes) {
    const bool huge = frameMemoryAdvisesHugePages(bytes);
    const std::size_t alignment = huge ? kHugePageBytes : kCacheLineBytes;
    const std::size_t size = roundUp(bytes == 0 ? 1 : bytes, alignment);
    std::unique_ptr<void, FrameMemoryRelease> memory(std::aligned_alloc(alignment, size));
    if (!memory) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Advice only: if the kernel refuses it the memory is ordinary pages, which is still correct.
    if (huge) static_cast<void>(madvise(memory.get(), size, MADV_HUGEPAGE));
#endif
    return memory;
}

}  // namespace patchsim
