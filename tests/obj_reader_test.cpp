#include "core/obj_reader.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

std::string errorOf(const std::string& text) {
    try {
        parseObjCage(text, "cage.obj");
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "cage.obj");
        return e.what();
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return {};
}

TEST(ObjReader, LoadsEveryOpenSubdivRegressionCage) {
    const auto files = test::regressionCageFiles();
    for (const std::string& path : files) {
        const Cage cage = readObjCage(path);
        EXPECT_GT(cage.vertexCount(), 0) << path;
        EXPECT_GT(cage.faceCount(), 0) << path;
    }
}

TEST(ObjReader, ReadsTagsOfTheCreasedCube) {
    const Cage cage = readObjCage(test::sourcePath("scenes/cages/catmark_cube_creases1.obj"));
    EXPECT_EQ(cage.vertexCount(), 8);
    EXPECT_EQ(cage.faceCount(), 6);
    ASSERT_FALSE(cage.creases.empty());
    EXPECT_EQ(cage.creases[0].v0, 0);
    EXPECT_EQ(cage.creases[0].v1, 1);
    EXPECT_FLOAT_EQ(cage.creases[0].sharpness, 5.0f);
}

TEST(ObjReader, ReadsCornersHolesAndBoundaryModes) {
    const Cage cage = parseObjCage(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
        "f 1 2 3 4\nf 2 5 6 3\n"
        "t corner 1/1/0 0 2.5\nt hole 1/0/0 1\nt interpolateboundary 1/0/0 1\n"
        "t crease 3/2/0 0 1 4 1.0 2.0\nt creasemethod 0/0/1 chaikin\nt vertexedit 0/0/0\n",
        "cage.obj");
    ASSERT_EQ(cage.corners.size(), 1u);
    EXPECT_FLOAT_EQ(cage.corners[0].sharpness, 2.5f);
    ASSERT_EQ(cage.holes.size(), 1u);
    EXPECT_EQ(cage.holes[0], 1);
    EXPECT_EQ(cage.boundary, BoundaryInterpolation::EdgeAndCorner);
    ASSERT_EQ(cage.creases.size(), 2u);
    EXPECT_FLOAT_EQ(cage.creases[1].sharpness, 2.0f);
    EXPECT_EQ(cage.creaseMethod, CreaseMethod::Chaikin);
    EXPECT_EQ(cage.warnings.size(), 1u);
}

TEST(ObjReader, NegativeIndicesAreRelative) {
    const Cage cage = parseObjCage("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3/1/1 -2 -1\n", "cage.obj");
    EXPECT_EQ(cage.faceVertices, (std::vector<int>{0, 1, 2}));
}

TEST(ObjReader, ErrorsNameFileLineAndColumn) {
    EXPECT_NE(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
                  .find("cage.obj: line 4, column 7: vertex index 7 out of range"),
              std::string::npos);
    EXPECT_NE(errorOf("v 0 zero 0\n").find("line 1, column 5: expected a number"),
              std::string::npos);
    EXPECT_NE(errorOf("v 0 0 nan\n").find("line 1"), std::string::npos);
    EXPECT_NE(errorOf("v 0 0 1e60\n").find("line 1"), std::string::npos);
    EXPECT_NE(errorOf("v 0 0\n").find("needs 3 coordinates"), std::string::npos);
    EXPECT_NE(errorOf("bogus 1 2\n").find("unknown OBJ statement 'bogus'"), std::string::npos);
    EXPECT_NE(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n").find("at least 3"), std::string::npos);
    EXPECT_NE(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt corner 1/1/0 9 1.0\n")
                  .find("line 5, column 16: tag vertex index 9 out of range"),
              std::string::npos);
    EXPECT_NE(
        errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt hole 1/0/0 4\n").find("tag face index 4"),
        std::string::npos);
    EXPECT_NE(
        errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0\n").find("declares 3 values"),
        std::string::npos);
    EXPECT_NE(
        errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 1 -1\n").find("sharpness"),
        std::string::npos);
}

// Coordinates are capped like every scene number (1e30): 3e38 is a float, but scaled by 2 it is
// infinite and the tessellation it touches NaN.
TEST(ObjReader, CoordinatesBeyondTheScenesNumberCapAreRefused) {
    const std::string face = "v 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n";
    EXPECT_NE(errorOf("v 3e38 0 0\n" + face)
                  .find("cage.obj: line 1, column 3: coordinate 3e38 is outside [-1e+30, 1e+30]"),
              std::string::npos);
    EXPECT_NE(errorOf("v 0 0 0\nv 0 -1.5e30 0\nv 0 1 0\nf 1 2 3\n")
                  .find("cage.obj: line 2, column 5: coordinate -1.5e30 is outside"),
              std::string::npos);
    const Cage atTheCap = parseObjCage("v 1e30 0 0\nv 0 -1e30 0\nv 0 1 0\nf 1 2 3\n", "cage.obj");
    EXPECT_EQ(atTheCap.positions[0].x, 1e30f);
    EXPECT_EQ(atTheCap.positions[1].y, -1e30f);
}

TEST(ObjReader, TagCountsAndValuesOutOfRangeAreErrorsNotOverflow) {
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    // Found by fuzzing: two counts near INT_MAX summed in int (undefined behaviour).
    EXPECT_NE(errorOf(triangle + "t crease 1174871153/0/1174871153 0 1\n")
                  .find("line 5, column 10: tag counts must be nint/nfloat/nstring, each 0 to"),
              std::string::npos);
    EXPECT_NE(errorOf(triangle + "t crease 99999999999999999999/0/0 0\n")
                  .find("line 5, column 10: expected an integer"),
              std::string::npos);
    EXPECT_NE(errorOf(triangle + "t crease 2/1\n").find("must be nint/nfloat/nstring"),
              std::string::npos);
    EXPECT_NE(errorOf(triangle + "t crease 2/1/0/4 0 1 2\n").find("must be nint/nfloat/nstring"),
              std::string::npos);
    EXPECT_NE(errorOf(triangle + "t crease -2/1/0 0 1 2\n").find("must be nint/nfloat/nstring"),
              std::string::npos);
    EXPECT_NE(errorOf(triangle + "t corner 1/1/0 4294967297 1.0\n")
                  .find("line 5, column 16: tag value 4294967297 is out of range"),
              std::string::npos);
}

TEST(ObjReader, RejectsEmptyAndBrokenMeshes) {
    EXPECT_NE(errorOf("").find("no vertices"), std::string::npos);
    EXPECT_NE(errorOf("v 0 0 0\n").find("no faces"), std::string::npos);
}

TEST(ObjReader, FacesThatRepeatAVertexAreDegenerateEdgesAsInOpenSubdiv) {
    // OpenSubdiv's non-manifold quad poles (catmark_nonman_quadpole*) have such faces; faces and
    // vertices are counted from 1, as OBJ does.
    const Cage cage =
        parseObjCage("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\nf 3 4 4\n", "pole.obj");
    ASSERT_EQ(cage.faceCount(), 2);
    ASSERT_FALSE(cage.warnings.empty());
    EXPECT_NE(cage.warnings[0].find("line 6: face 2 repeats vertex 4"), std::string::npos)
        << cage.warnings[0];
}

TEST(ObjReader, NonManifoldEdgesAreAcceptedWithAWarning) {
    // OpenSubdiv handles them (catmark_fan has one), so the reader warns instead of failing.
    const Cage cage =
        parseObjCage("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nf 1 2 3\nf 1 2 4\n", "c.obj");
    ASSERT_EQ(cage.warnings.size(), 1u);
    EXPECT_NE(cage.warnings[0].find("non-manifold edge 1-2 (faces 1 and 2"), std::string::npos)
        << cage.warnings[0];
}

}  // namespace
}  // namespace patchsim
