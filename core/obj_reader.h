#pragma once
// Reads OBJ control cages with OpenSubdiv's tag lines.
//
// Representation
// --------------
// A cage is the base mesh of a subdivision surface: vertex positions, and faces as a flat list of
// vertex indices with a per-face size (the layout Far::TopologyDescriptor takes directly). Tags
// follow OpenSubdiv's regression shapes: `t NAME nint/nfloat/nstring ints... floats... strings...`.
// Creases are vertex chains with one sharpness for the chain or one per edge; corners are vertices
// with one sharpness or one each; holes are face indices. Texture coordinates and normals are
// read past (the surface defines its own). Hierarchical edits are skipped with a warning.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"

namespace patchsim {

enum class BoundaryInterpolation : std::uint8_t { None, EdgeOnly, EdgeAndCorner };
enum class CreaseMethod : std::uint8_t { Uniform, Chaikin };

struct CageCrease {
    int v0, v1;
    float sharpness;
};

struct CageCorner {
    int vertex;
    float sharpness;
};

struct Cage {
    std::vector<Vec3> positions;
    std::vector<int> faceSizes;
    std::vector<int> faceVertices;  // concatenated, faceSizes[i] per face
    std::vector<CageCrease> creases;
    std::vector<CageCorner> corners;
    std::vector<int> holes;
    BoundaryInterpolation boundary = BoundaryInterpolation::EdgeOnly;
    CreaseMethod creaseMethod = CreaseMethod::Uniform;
    bool smoothTriangles = false;  // Catmark "smooth triangle" rule
    std::vector<std::string> warnings;

    int faceCount() const { return static_cast<int>(faceSizes.size()); }
    int vertexCount() const { return static_cast<int>(positions.size()); }
};

// Throws InputError naming the file and "line L, column C" for any malformed line, index out of
// range, non-finite coordinate, or an empty or degenerate mesh.
Cage parseObjCage(std::string_view text, const std::string& path);
Cage readObjCage(const std::string& path, const std::string& referringFile = {},
                 const std::string& field = {});

}  // namespace patchsim
