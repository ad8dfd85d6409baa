// The image module (image_io_module.h): every call patchsim makes into OpenImageIO. Built as a
// shared module and loaded with dlopen; nothing else in patchsim includes an OpenImageIO header.

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <exception>

#include "backend/images/image_io_module.h"

namespace patchsim {
namespace {

// Runs `call`, turning anything it throws into `error`: no exception leaves the module.
template <typename Call>
bool guarded(std::string& error, const Call& call) {
    try {
        return call();
    } catch (const std::exception& e) {
        error = e.what();
    } catch (...) {
        error = "unknown error in OpenImageIO";
    }
    return false;
}

bool writePixels(const ImageWriteRequest& request, std::string& error) {
    OIIO::ImageSpec spec(request.width, request.height, request.channels,
                         request.uint8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (!request.channelNames.empty()) spec.channelnames = request.channelNames;
    for (std::size_t c = 0; c < request.channelNames.size(); ++c)
        if (request.channelNames[c] == "Z") spec.z_channel = int(c);
    if (request.zipCompression) spec.attribute("compression", "zip");
    // No capture date: the same frame must give the same file, byte for byte.
    spec.attribute("DateTime", "");
    OIIO::attribute("exr_threads", request.threads);
    auto out = OIIO::ImageOutput::create(request.path);
    if (!out) {
        error = "no image writer for this file type";
        return false;
    }
    if (!out->open(request.path, spec) || !out->write_image(spec.format, request.pixels) ||
        !out->close()) {
        error = "cannot write image: " + out->geterror();
        return false;
    }
    return true;
}

bool readFile(const std::string& path, bool pixels, ImageFileContents& out, std::string& error) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        error = "cannot read image: " + OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    out.width = spec.width;
    out.height = spec.height;
    out.channelNames = spec.channelnames;
    if (!pixels) return true;
    out.pixels.resize(std::size_t(spec.width) * std::size_t(spec.height) *
                      std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.pixels.data())) {
        error = "cannot read image: " + in->geterror();
        return false;
    }
    return true;
}

bool drawText(const TextRequest& request, std::string& error) {
    OIIO::ImageBuf image(OIIO::ImageSpec(request.width, request.height, 3, OIIO::TypeDesc::UINT8),
                         request.rgb);
    const auto align = request.alignRight ? OIIO::ImageBufAlgo::TextAlignX::Right
                                          : OIIO::ImageBufAlgo::TextAlignX::Left;
    if (!OIIO::ImageBufAlgo::render_text(image, request.x, request.y, request.text, request.size,
                                         request.font, request.color, align)) {
        error = "cannot draw text: " + image.geterror();
        return false;
    }
    return true;
}

bool guardedWrite(const ImageWriteRequest& request, std::string& error) {
    return guarded(error, [&] { return writePixels(request, error); });
}
bool guardedRead(const std::string& path, bool pixels, ImageFileContents& out, std::string& error) {
    return guarded(error, [&] { return readFile(path, pixels, out, error); });
}
bool guardedDrawText(const TextRequest& request, std::string& error) {
    return guarded(error, [&] { return drawText(request, error); });
}

constexpr ImageIoTable kTable{kImageIoVersion, guardedWrite, guardedRead, guardedDrawText};

}  // namespace
}  // namespace patchsim

extern "C" const patchsim::ImageIoTable* patchsim_image_io() {
    return &patchsim::kTable;
}
