#pragma once
// What an image-space method's full-screen passes read and wrote after the resolve (the
// post-process's TileMax, NeighbourMax and gather; the hybrid's mask passes), recorded by the
// functional filter for the memory model (pipeline/timing/memory_model.h) to replay through the
// image cache. Part of a MemoryTrace; recorded only when the hardware models memory.
//
// Representation
// --------------
// Planes are row-major arrays of one element per pixel (or per tile), each `elementBytes` long.
// The first planes are the resolved images (8 bytes a pixel, where the resolves wrote them: the
// frame's, then a later frame's, as reprojection renders two); a method declares the rest (depth,
// velocity, tile maxima, its output) with `addPlane`, and the memory model lays them out one after
// another. A pass is its accesses in the order the filter made them: an element index and 16 bits
// holding a mask of the planes accessed at that index (a gather tap reads a pixel's colour, depth
// and velocity in one access) and whether it is a write, or an update (read, modified and written:
// an accumulation buffer's blend, replayed as a write, whose miss brings the line in, and counted
// as both). Six bytes an access; no addresses, so one trace serves every layout and cache size.
// An access that repeats the one before it exactly (a sample reprojected into the same pixel by
// consecutive cameras) adds only its bytes to the pass's count: the replay would merge it with
// the one before (they touch the same lines).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace patchsim {

struct ImagePlane {
    std::string name;  // "velocity", for reports and tests
    std::uint64_t elements = 0;
    std::uint32_t elementBytes = 0;
};

struct ImagePass {
    std::string name;  // "gather"
    std::vector<std::uint32_t> elements;
    std::vector<std::uint16_t> planes;  // a mask of planes 0..13, and kImageWrite or kImageUpdate
    // Accesses that repeated the one before them exactly, kept as a count of their bytes only
    // (the replay would merge them anyway: they touch the same lines).
    std::uint64_t repeatedReadBytes = 0, repeatedWriteBytes = 0;
};

inline constexpr std::uint16_t kImageWrite = 0x8000, kImageUpdate = 0x4000;
inline constexpr int kMaxImagePlanes = 14;
// An access reads its planes unless it is a plain write; it writes them if a write or an update.
constexpr bool accessReads(std::uint16_t planes) {
    return (planes & kImageWrite) == 0;
}
constexpr bool accessWrites(std::uint16_t planes) {
    return (planes & (kImageWrite | kImageUpdate)) != 0;
}
inline constexpr std::uint32_t kResolvedImagePixelBytes = 8;  // RGBA at 16 bits

class ImagePassTrace {
  public:
    // The resolved images of `width` x `height` pixels are planes 0 to `resolvedFrames` - 1.
    ImagePassTrace(int width, int height, int resolvedFrames = 1);

    // Declares a plane; returns its mask bit. Throws std::logic_error past kMaxImagePlanes.
    std::uint16_t addPlane(std::string name, std::uint64_t elements, std::uint32_t elementBytes);
    static constexpr std::uint16_t resolvedImage(int frame = 0) {
        return std::uint16_t(1u << frame);
    }
    int resolvedFrames() const { return resolvedFrames_; }

    void beginPass(std::string name);
    void read(std::uint16_t planeMask, std::size_t element) { add(planeMask, element); }
    void write(std::uint16_t planeMask, std::size_t element) {
        add(std::uint16_t(planeMask | kImageWrite), element);
    }
    void update(std::uint16_t planeMask, std::size_t element) {
        add(std::uint16_t(planeMask | kImageUpdate), element);
    }

    const std::vector<ImagePlane>& planes() const { return planes_; }
    const std::vector<ImagePass>& passes() const { return passes_; }
    // The bytes a pass's reads (or writes) touched: each access's planes' element sizes.
    std::uint64_t passBytes(const ImagePass& pass, bool writes) const;
    std::uint64_t bytes() const;  // what the trace holds

  private:
    void add(std::uint16_t planes, std::size_t element);
    std::uint64_t elementBytes(std::uint16_t planes) const;

    int resolvedFrames_;
    std::vector<ImagePlane> planes_;
    std::vector<ImagePass> passes_;
};

}  // namespace patchsim
