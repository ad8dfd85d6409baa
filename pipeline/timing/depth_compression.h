#pragma once
// Lossless depth compression of the modelled hardware, block by block of the depth surface
// (memory_model.h's layout blocks), measured on a frame's final depth: how many bits each block
// needs, so DRAM's depth traffic can be charged at that size and a user sees how motion blur and
// defocus erode compression (Andersson et al., HPG 2011: about 65% of the uncompressed size under
// moderate motion, against 75% for the previous best stochastic scheme).
//
// Representation
// --------------
// A block's samples are clear (no hit: the fast-clear value, no bits), or hits. A hit's depth d
// is predicted from its inverse, which is affine in screen position for a plane seen through a
// pinhole: w = 1/d fitted by least squares over the block's hits, as
//
//   plane:       w = a + b x + c y                  (x, y: the sample's raster position)
//   time_plane:  w = a + b x + c y + e t + f u + g v (t: its time; u, v: its lens position)
//
// The first is the static plane encoding of conventional depth compressors; the second is a
// time-dependent predictor after Andersson et al. 2011, with the lens terms added for defocus.
// Each hit stores the difference between its depth's float bits and the prediction's, all at the
// block's widest difference (a sign and the magnitude's bits). The hits may be split into two
// clusters at the middle of their inverse depths, each with its own predictor (a foreground and a
// background surface), when that is smaller. Per block:
//
//   bits = [a selector per sample when the block mixes clear samples and clusters]
//        + per cluster: the predictor's coefficients (32 bits each) + 5 bits of residual width
//                       + that width for each of its hits,
//
// never more than the uncompressed 32 bits a sample (then the block is stored raw). A block of
// clear samples only is 0 bits: the tile table says it is clear.

#include <cstdint>
#include <vector>

#include "core/samples.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

enum class DepthCompression : std::uint8_t { None, Plane, TimePlane };
const char* depthCompressionName(DepthCompression c);  // "none", "plane", "time_plane"
bool parseDepthCompression(const std::string& name, DepthCompression& out);

// The depth samples of one block, as the compressor sees them.
struct DepthSample {
    bool hit = false;
    float depth = 0;
    float x = 0, y = 0;  // raster position
    float time = 0, u = 0, v = 0;
};

// The bits one block takes under `scheme` (DepthCompression::None: 32 a sample).
std::uint64_t compressedBlockBits(const std::vector<DepthSample>& samples, DepthCompression scheme);

struct DepthCompressionReport {
    DepthCompression scheme = DepthCompression::None;
    std::vector<std::uint64_t> blockBits;     // per layout block, row-major
    std::vector<std::uint32_t> blockSamples;  // its samples (fewer at the frame's edges)
    std::uint64_t compressedBits = 0, uncompressedBits = 0;  // over blocks with a hit
    std::uint64_t clearBlocks = 0;

    // The compressed size over the uncompressed, for the blocks holding geometry.
    double ratio() const {
        return uncompressedBits ? double(compressedBits) / double(uncompressedBits) : 0.0;
    }
    // Per block, its compressed size over its uncompressed one (0 for a clear block).
    std::vector<double> blockScales() const;
};

// Every layout block of `surfaceTile` x `surfaceTile` pixels of the frame's final depth, its
// samples placed by `samples` (the frame's sample set).
DepthCompressionReport compressDepth(const VisibilityBuffer& buffer, const SampleGenerator& samples,
                                     int surfaceTile, DepthCompression scheme);

}  // namespace patchsim
