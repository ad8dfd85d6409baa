#include "backend/images/image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace patchsim {

namespace {

// Writes `path` (format from its extension); callers stage it through an OutputSet.
void writeImage(const std::string& path, OIIO::ImageSpec spec, const void* pixels) {
    // No capture date: the same frame must give the same file, byte for byte.
    spec.attribute("DateTime", "");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw InputError(path, "", "no image writer for this file type");
    if (!out->open(path, spec) || !out->write_image(spec.format, pixels) || !out->close())
        throw InputError(path, "", "cannot write image: " + out->geterror());
}

}  // namespace

float linearToSrgb(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void writeFloatChannels(const std::string& path, int width, int height,
                        const std::vector<std::string>& names, std::span<const float> pixels) {
    OIIO::ImageSpec spec(width, height, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    for (std::size_t c = 0; c < names.size(); ++c)
        if (names[c] == "Z") spec.z_channel = int(c);
    spec.attribute("compression", "zip");
    writeImage(path, spec, pixels.data());
}

void writeExr(const Image& image, const std::string& path) {
    writeFloatChannels(path, image.width, image.height, {"R", "G", "B"}, image.rgb);
}

void writePng(const Image& image, const std::string& path) {
    std::vector<unsigned char> bytes(image.rgb.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<unsigned char>(std::lround(linearToSrgb(image.rgb[i]) * 255.0f));
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    writeImage(path, spec, bytes.data());
}

std::vector<std::string> readChannelNames(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError(path, "", "cannot read image: " + OIIO::geterror());
    return in->spec().channelnames;
}

std::vector<float> readChannel(const std::string& path, const std::string& name) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError(path, "", "cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    const int c = spec.channelindex(name);
    if (c < 0) throw InputError(path, name, "the image has no such channel");
    std::vector<float> values(std::size_t(spec.width) * std::size_t(spec.height));
    in->read_image(0, 0, c, c + 1, OIIO::TypeDesc::FLOAT, values.data());
    return values;
}

Image readImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError(path, "", "cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    Image image(spec.width, spec.height);
    std::vector<float> all(std::size_t(spec.width) * std::size_t(spec.height) *
                           std::size_t(spec.nchannels));
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data());
    for (std::size_t p = 0; p < std::size_t(spec.width) * std::size_t(spec.height); ++p)
        for (int c = 0; c < 3; ++c)
            image.rgb[p * 3 + std::size_t(c)] =
                all[p * std::size_t(spec.nchannels) + std::size_t(std::min(c, spec.nchannels - 1))];
    return image;
}

}  // namespace patchsim
