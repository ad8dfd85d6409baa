#pragma once
// How a frame is cut into parts that workers and processes own (DESIGN.md section 13).
//
// Representation
// --------------
// A frame falls into kClasses classes of rows. A tiled method (the patch rasterizer) puts tile
// row ty in class ty % kClasses, so a process that owns some classes holds rows spread over the
// frame and the work evens out; a method without tiles cuts the frame into kClasses horizontal
// bands, band b being the pixel rows [b H / kClasses, (b + 1) H / kClasses). A process (MPI rank r
// of n) owns the classes c with c % n == r; one process owns them all. The classes are fixed, so
// the split, and with it every count, is the same for any number of processes; within a process,
// workers take tiles or bands as they come, each writing transparent layers from a pool of its
// own (transparent_layers.h), so the worker count is free too.

namespace patchsim {

struct FramePartition {
    static constexpr int kClasses = 16;

    int rank = 0, ranks = 1;

    bool split() const { return ranks > 1; }
    bool ownsClass(int rowClass) const { return rowClass % ranks == rank; }

    static int classOfTileRow(int ty) { return ty % kClasses; }
    bool ownsTileRow(int ty) const { return ownsClass(classOfTileRow(ty)); }
    // A pixel row of a tiled frame, by the class of its tile's row.
    bool ownsTiledPixelRow(int y, int tileSize) const { return ownsTileRow(y / tileSize); }

    // The first pixel row of `band` (its end: bandBegin(band + 1, height)).
    static int bandBegin(int band, int height) { return band * height / kClasses; }
    static int bandOf(int y, int height);
    bool ownsBandPixelRow(int y, int height) const { return ownsClass(bandOf(y, height)); }
};

}  // namespace patchsim
