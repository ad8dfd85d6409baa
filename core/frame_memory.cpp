#include "core/frame_memory.h"

#include <array>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <new>
#include <string>
#include <utility>

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

std::size_t frameAlignment(std::size_t bytes) {
    return frameMemoryAdvisesHugePages(bytes) ? kHugePageBytes : kCacheLineBytes;
}

}  // namespace

bool frameMemoryAdvisesHugePages(std::size_t bytes) {
    return bytes >= kSmallestHugePageBuffer && hugePagesWanted();
}

namespace {

// Frame-sized blocks given back since the last request the cache could not serve (see the header).
// A fixed array, so that keeping a block (in a noexcept release) never allocates.
class BlockCache {
  public:
    static BlockCache& instance() {
        static BlockCache* const cache = new BlockCache;  // outlives static destruction
        return *cache;
    }

    // A block of exactly `size` bytes; or, when there is none, nullptr after every cached block is
    // given back.
    void* take(std::size_t size) {
        {
            std::lock_guard lock(mutex_);
            for (std::size_t i = 0; i < count_; ++i) {
                if (blocks_[i].size != size) continue;
                void* memory = blocks_[i].memory;
                cachedBytes_ -= size;
                blocks_[i] = blocks_[--count_];
                return memory;
            }
        }
        clear();
        return nullptr;
    }

    // Gives every cached block back (outside the lock: freeing may take a while).
    void clear() {
        std::array<Block, kMaxCachedBlocks> unused;
        std::size_t unusedCount = 0;
        {
            std::lock_guard lock(mutex_);
            unused = blocks_;
            unusedCount = std::exchange(count_, 0);
            cachedBytes_ = 0;
        }
        for (std::size_t i = 0; i < unusedCount; ++i)
            ::operator delete(unused[i].memory, std::align_val_t(unused[i].alignment));
    }

    // Whether the cache kept the block.
    bool keep(void* memory, std::size_t size, std::size_t alignment) noexcept {
        std::lock_guard lock(mutex_);
        if (count_ == kMaxCachedBlocks || cachedBytes_ + size > kMaxCachedBytes) return false;
        blocks_[count_++] = {memory, size, alignment};
        cachedBytes_ += size;
        return true;
    }

    std::size_t bytes() {
        std::lock_guard lock(mutex_);
        return cachedBytes_;
    }

  private:
    static constexpr std::size_t kMaxCachedBlocks = 16;
    static constexpr std::size_t kMaxCachedBytes = std::size_t(1) << 30;

    struct Block {
        void* memory = nullptr;
        std::size_t size = 0, alignment = 0;
    };
    std::mutex mutex_;
    std::array<Block, kMaxCachedBlocks> blocks_;
    std::size_t count_ = 0, cachedBytes_ = 0;
};

}  // namespace

void* allocateFrameBytes(std::size_t bytes) {
    const std::size_t alignment = frameAlignment(bytes);
    const std::size_t size = roundUp(bytes == 0 ? 1 : bytes, alignment);
    if (bytes >= kSmallestHugePageBuffer)
        if (void* reused = BlockCache::instance().take(size)) return reused;
    void* memory = ::operator new(size, std::align_val_t(alignment));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Advice only: if the kernel refuses it the memory is ordinary pages, which is still correct.
    if (alignment == kHugePageBytes) static_cast<void>(madvise(memory, size, MADV_HUGEPAGE));
#endif
    return memory;
}

void releaseFrameBytes(void* p, std::size_t bytes) noexcept {
    const std::size_t alignment = frameAlignment(bytes);
    if (bytes >= kSmallestHugePageBuffer &&
        BlockCache::instance().keep(p, roundUp(bytes, alignment), alignment))
        return;
    ::operator delete(p, std::align_val_t(alignment));
}

void releaseCachedFrameMemory() {
    BlockCache::instance().clear();
}

std::size_t cachedFrameMemoryBytes() {
    return BlockCache::instance().bytes();
}

}  // namespace patchsim
