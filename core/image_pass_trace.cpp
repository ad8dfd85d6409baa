#include "core/image_pass_trace.h"

#include <stdexcept>

namespace patchsim {

ImagePassTrace::ImagePassTrace(int width, int height, int resolvedFrames)
    : resolvedFrames_(resolvedFrames) {
    if (resolvedFrames < 1 || resolvedFrames >= kMaxImagePlanes)
        throw std::logic_error("an image-space trace follows 1 to 13 resolved frames");
    for (int f = 0; f < resolvedFrames; ++f)
        planes_.push_back({f == 0 ? "resolved image" : "later resolved image",
                           std::uint64_t(width) * std::uint64_t(height), kResolvedImagePixelBytes});
}

std::uint16_t ImagePassTrace::addPlane(std::string name, std::uint64_t elements,
                                       std::uint32_t elementBytes) {
    if (planes_.size() >= std::size_t(kMaxImagePlanes))
        throw std::logic_error("an image-space trace holds at most 14 planes");
    planes_.push_back({std::move(name), elements, elementBytes});
    return std::uint16_t(1u << (planes_.size() - 1));
}

void ImagePassTrace::beginPass(std::string name) {
    passes_.push_back({std::move(name), {}, {}});
}

void ImagePassTrace::add(std::uint16_t planes, std::size_t element) {
    ImagePass& pass = passes_.back();
    if (!pass.elements.empty() && pass.elements.back() == element && pass.planes.back() == planes) {
        const std::uint64_t bytes = elementBytes(planes);
        if (accessReads(planes)) pass.repeatedReadBytes += bytes;
        if (accessWrites(planes)) pass.repeatedWriteBytes += bytes;
        return;
    }
    pass.elements.push_back(std::uint32_t(element));
    pass.planes.push_back(planes);
}

std::uint64_t ImagePassTrace::elementBytes(std::uint16_t planes) const {
    std::uint64_t bytes = 0;
    for (std::size_t p = 0; p < planes_.size(); ++p)
        if (planes >> p & 1u) bytes += planes_[p].elementBytes;
    return bytes;
}

std::uint64_t ImagePassTrace::passBytes(const ImagePass& pass, bool writes) const {
    std::uint64_t bytes = writes ? pass.repeatedWriteBytes : pass.repeatedReadBytes;
    for (std::uint16_t planes : pass.planes) {
        if (writes ? accessWrites(planes) : accessReads(planes)) bytes += elementBytes(planes);
    }
    return bytes;
}

std::uint64_t ImagePassTrace::bytes() const {
    std::uint64_t n = 0;
    for (const ImagePass& pass : passes_)
        n += pass.elements.size() * (sizeof(std::uint32_t) + sizeof(std::uint16_t));
    return n;
}

}  // namespace patchsim
