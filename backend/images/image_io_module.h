#pragma once
// The boundary between patchsim and OpenImageIO, which lives in a module loaded on first use.
//
// Why a module
// ------------
// Debian's OpenImageIO links 263 shared libraries (codecs, OpenCV, GStreamer, GDAL, ...); binding
// them takes about 0.4 s of every process, longer than a default render's work. Only a module that
// patchsim loads with dlopen keeps that cost off the commands that write no image (`--help`,
// `info`, `verify-tiles`) and lets `render` load it on a side thread while the frame is computed
// (preloadImageIo), so the cost overlaps the work instead of preceding it.
//
// Representation
// --------------
// The module exports one C function, `patchsim_image_io`, returning a table of three calls: write
// interleaved pixels, read a whole file as float, draw text into an 8-bit RGB buffer. Every call
// reports failure as a message (each catches what OpenImageIO throws, so no exception crosses the
// boundary); image.cpp and heat_map.cpp turn it into an InputError naming the file. The table
// carries a version so that a stale module is refused rather than called with the wrong layout.

#include <cstdint>
#include <string>
#include <vector>

namespace patchsim {

inline constexpr int kImageIoVersion = 1;

struct ImageWriteRequest {
    std::string path;  // format from the extension
    int width = 0, height = 0;
    std::vector<std::string> channelNames;  // empty: the format's defaults (R, G, B)
    int channels = 0;
    bool uint8 = false;            // false: 32-bit float
    bool zipCompression = false;   // EXR's lossless zip
    int threads = 1;               // the writer's compression threads
    const void* pixels = nullptr;  // interleaved, row-major
};

struct ImageFileContents {
    int width = 0, height = 0;
    std::vector<std::string> channelNames;
    std::vector<float> pixels;  // interleaved, row-major
};

struct TextRequest {
    std::uint8_t* rgb = nullptr;  // 8-bit RGB, row-major, width * height * 3
    int width = 0, height = 0;
    int x = 0, y = 0;  // baseline start (or end, when alignRight)
    std::string text;
    int size = 12;
    std::string font;
    float color[3] = {1, 1, 1};
    bool alignRight = false;
};

struct ImageIoTable {
    int version;
    bool (*write)(const ImageWriteRequest& request, std::string& error);
    bool (*read)(const std::string& path, bool pixels, ImageFileContents& out, std::string& error);
    bool (*drawText)(const TextRequest& request, std::string& error);
};

// The module's file: $PATCHSIM_IMAGE_IO_MODULE when set; else the one this build made (its
// absolute path in the build tree); else libpatchsim_image_io.so beside the running program.
// Throws InputError naming where it looked when there is none.
std::string imageIoModulePath();

// The module's table, loaded on the first call (and waiting for a preload under way); throws
// InputError naming the module when it cannot be loaded.
const ImageIoTable& imageIo();

// Refuses a missing module at once (imageIoModulePath), then starts loading it on a side thread
// and returns; the process joins that thread
// before it exits. Commands that will write images call it first, after starting their worker
// threads. While the load runs, glibc's loader lock is held: a thread that starts then (its TLS
// set-up takes that lock), or that first touches a thread_local with a destructor (its
// registration takes it too), waits for the whole load. So the workers start before it, and
// patchsim keeps no thread_local with a destructor (core/counters.cpp).
void preloadImageIo();

}  // namespace patchsim

extern "C" const patchsim::ImageIoTable* patchsim_image_io();
