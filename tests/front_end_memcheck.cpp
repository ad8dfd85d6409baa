// Runs the front end (IA, VS, HS, TS, DS) over every patch of the cages given on the command line.
// CTest runs it under valgrind on the cages that make OpenSubdiv 3.5.0's Bfr read uninitialised
// memory: any such read fails the test, whether or not it happens to crash. (It links only the
// tessellator, so valgrind need not run the image libraries.)

#include <cstdio>

#include "core/error.h"
#include "core/scene_reader.h"
#include "tessellator/front_end.h"

int main(int argc, char** argv) {
    using namespace patchsim;
    try {
        for (int i = 1; i < argc; ++i) {
            const FrontEnd frontEnd(sceneForCage(argv[i]));
            FrontEndWorkspace workspace = frontEnd.makeWorkspace();
            TessellatedPatch patch;
            std::size_t points = 0;
            for (std::size_t p = 0; p < frontEnd.patchCount(); ++p) {
                frontEnd.tessellate(p, patch, workspace);
                points += patch.position[0].size();
            }
            std::printf("%s: %zu patches, %zu points evaluated\n", argv[i], frontEnd.patchCount(),
                        points);
        }
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
    return 0;
}
