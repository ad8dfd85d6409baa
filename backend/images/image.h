#pragma once
// Linear float RGB images and their output through OpenImageIO: EXR keeps linear values, PNG is
// 8-bit sRGB. The writers write the path they are given; commands stage it through an OutputSet
// (core/output_set.h) so that a failure leaves nothing behind.

#include <span>
#include <string>
#include <vector>

#include "core/frame_memory.h"
#include "core/math.h"

namespace patchsim {

// A frame-sized plane of floats in frame memory (huge pages where advised): sized construction
// leaves it unwritten (see default_init_allocator.h), for outputs whose every element the workers
// write.
using FloatPlane = std::vector<float, FrameAllocator<float>>;

struct Image {
    int width = 0, height = 0;
    FloatPlane rgb;  // row-major, 3 floats per pixel, linear

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0.0f) {}
    // Every pixel left for the caller to set, on the threads that set them: no serial zero-fill.
    static Image unfilled(int w, int h) {
        Image image;
        image.width = w;
        image.height = h;
        image.rgb = FloatPlane(std::size_t(w) * std::size_t(h) * 3);
        return image;
    }
    Vec3 get(int x, int y) const {
        const std::size_t i = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
    void set(int x, int y, const Vec3& c) {
        const std::size_t i = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
        rgb[i] = c.x;
        rgb[i + 1] = c.y;
        rgb[i + 2] = c.z;
    }
};

// Throws InputError(path, ...) when the file cannot be written.
void writeExr(const Image& image, const std::string& path);
// Float channels, interleaved per pixel, with their names (EXR or any float format).
void writeFloatChannels(const std::string& path, int width, int height,
                        const std::vector<std::string>& names, std::span<const float> pixels);
void writePng(const Image& image, const std::string& path);
// 8-bit RGB, row-major, width * height * 3 bytes (PNG or any 8-bit format).
void writeRgb8(const std::string& path, int width, int height, const unsigned char* rgb);
// Threads the writers may compress with (the job's --threads; 1 until a command sets it).
void setImageWriterThreads(int threads);
Image readImage(const std::string& path);  // for tests and tools; float RGB
std::vector<std::string> readChannelNames(const std::string& path);
// One named channel of an image file, row-major; throws InputError when it has none.
std::vector<float> readChannel(const std::string& path, const std::string& name);

float linearToSrgb(float linear);

}  // namespace patchsim
