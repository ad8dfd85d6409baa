#include "backend/images/image.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "backend/images/image_io_module.h"
#include "core/error.h"

namespace patchsim {

namespace {

std::atomic<int> writerThreads{1};

// Writes `request.path`; callers stage it through an OutputSet.
void writeImage(ImageWriteRequest request) {
    request.threads = writerThreads.load();
    std::string error;
    if (!imageIo().write(request, error)) throw InputError(request.path, "", error);
}

ImageFileContents readFile(const std::string& path, bool pixels) {
    ImageFileContents contents;
    std::string error;
    if (!imageIo().read(path, pixels, contents, error)) throw InputError(path, "", error);
    return contents;
}

}  // namespace

void setImageWriterThreads(int threads) {
    writerThreads = std::max(threads, 1);
}

float linearToSrgb(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void writeFloatChannels(const std::string& path, int width, int height,
                        const std::vector<std::string>& names, std::span<const float> pixels) {
    ImageWriteRequest request;
    request.path = path;
    request.width = width;
    request.height = height;
    request.channelNames = names;
    request.channels = int(names.size());
    request.zipCompression = true;
    request.pixels = pixels.data();
    writeImage(request);
}

void writeExr(const Image& image, const std::string& path) {
    writeFloatChannels(path, image.width, image.height, {"R", "G", "B"}, image.rgb);
}

void writePng(const Image& image, const std::string& path) {
    std::vector<unsigned char> bytes(image.rgb.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<unsigned char>(std::lround(linearToSrgb(image.rgb[i]) * 255.0f));
    writeRgb8(path, image.width, image.height, bytes.data());
}

void writeRgb8(const std::string& path, int width, int height, const unsigned char* rgb) {
    ImageWriteRequest request;
    request.path = path;
    request.width = width;
    request.height = height;
    request.channels = 3;
    request.uint8 = true;
    request.pixels = rgb;
    writeImage(request);
}

std::vector<std::string> readChannelNames(const std::string& path) {
    return readFile(path, false).channelNames;
}

std::vector<float> readChannel(const std::string& path, const std::string& name) {
    const ImageFileContents file = readFile(path, true);
    const auto found = std::find(file.channelNames.begin(), file.channelNames.end(), name);
    if (found == file.channelNames.end())
        throw InputError(path, name, "the image has no such channel");
    const std::size_t c = std::size_t(found - file.channelNames.begin());
    const std::size_t channels = file.channelNames.size();
    std::vector<float> values(std::size_t(file.width) * std::size_t(file.height));
    for (std::size_t p = 0; p < values.size(); ++p) values[p] = file.pixels[p * channels + c];
    return values;
}

Image readImage(const std::string& path) {
    const ImageFileContents file = readFile(path, true);
    const std::size_t channels = file.channelNames.size();
    Image image(file.width, file.height);
    for (std::size_t p = 0; p < std::size_t(file.width) * std::size_t(file.height); ++p)
        for (std::size_t c = 0; c < 3; ++c)
            image.rgb[p * 3 + c] = file.pixels[p * channels + std::min(c, channels - 1)];
    return image;
}

}  // namespace patchsim
