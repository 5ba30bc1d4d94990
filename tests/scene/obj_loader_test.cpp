// The native OBJ reader behind mesh_from_obj (lua/README.md, "Entities").
#include "scene/obj_loader.h"
#include "util/scene_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace lray {
namespace {

std::string errorOf(const std::string &text) {
  try {
    parseObj(text, "model.obj");
  } catch (const SceneError &e) {
    return e.what();
  }
  return "";
}

TEST(ObjLoaderTest, AllFourCornerForms) {
  MeshSource m = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                          "vt 0 0\nvt 1 0\nvt 0 1\n"
                          "vn 0 0 -1\n"
                          "f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1\n",
                          "model.obj");
  ASSERT_EQ(m.positions.size(), 3u);
  ASSERT_EQ(m.uvs.size(), 3u);
  ASSERT_EQ(m.normals.size(), 1u);
  ASSERT_EQ(m.faceSizes, (std::vector<uint32_t>{3, 3, 3, 3}));
  ASSERT_EQ(m.corners.size(), 12u);
  EXPECT_EQ(m.corners[1].v, 1);
  EXPECT_EQ(m.corners[1].uv, -1);
  EXPECT_EQ(m.corners[1].n, -1);
  EXPECT_EQ(m.corners[4].uv, 1);
  EXPECT_EQ(m.corners[4].n, -1);
  EXPECT_EQ(m.corners[7].uv, -1);
  EXPECT_EQ(m.corners[7].n, 0);
  EXPECT_EQ(m.corners[11].v, 2);
  EXPECT_EQ(m.corners[11].uv, 2);
  EXPECT_EQ(m.corners[11].n, 0);
  EXPECT_EQ(m.positions[1].x, 1);
  EXPECT_EQ(m.uvs[2].v, 1);
  EXPECT_EQ(m.normals[0].z, -1);
}

TEST(ObjLoaderTest, NegativeIndicesAreRelativeToWhatWasReadSoFar) {
  MeshSource m = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf -3/-1 -2/-1 -1/-1\n"
                          "v 5 5 5\nf -4 -3 -1\n",
                          "model.obj");
  ASSERT_EQ(m.corners.size(), 6u);
  EXPECT_EQ(m.corners[0].v, 0);
  EXPECT_EQ(m.corners[2].v, 2);
  EXPECT_EQ(m.corners[0].uv, 0);
  EXPECT_EQ(m.corners[3].v, 0);
  EXPECT_EQ(m.corners[5].v, 3);
}

TEST(ObjLoaderTest, PolygonsAreKeptWholeForFanning) {
  MeshSource m =
      parseObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 1 0\nf 1 2 3 4 5\n", "model.obj");
  EXPECT_EQ(m.faceSizes, (std::vector<uint32_t>{5}));
  EXPECT_EQ(m.corners.size(), 5u);
}

TEST(ObjLoaderTest, CrlfCommentsTrailingSpacesAndIgnoredStatements) {
  MeshSource m = parseObj("# exported\r\nmtllib a.mtl\r\no thing\r\nv 0 0 0   \r\nv 1 0 0\t\r\n"
                          "v 0 1 0 1.0\r\ng part\r\nusemtl red\r\ns off\r\n\r\n"
                          "f 1 2 3 # a comment\r\nl 1 2\r\nvt 0.25 0.5 0\r\n",
                          "model.obj");
  EXPECT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.faceSizes.size(), 1u); // nothing silently dropped
  ASSERT_EQ(m.uvs.size(), 1u);
  EXPECT_EQ(m.uvs[0].u, 0.25f);
  EXPECT_EQ(m.uvs[0].v, 0.5f);
}

TEST(ObjLoaderTest, MalformedLinesNameThePathAndLine) {
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0\n"), "model.obj:2: 'v' needs 3 to 7 numbers, got 2");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 x 0\n"), "model.obj:2: expected a number, got 'x'");
  EXPECT_EQ(errorOf("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 4\r\n"),
            "model.obj:4: vertex index 4 is out of range (3 so far)");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n"),
            "model.obj:4: vertex index -4 is out of range (3 so far)");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2 3\n"),
            "model.obj:4: uv index 1 is out of range (0 so far)");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
            "model.obj:4: face needs at least 3 corners, got 2");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"),
            "model.obj:4: malformed vertex index '0'");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n"),
            "model.obj:4: malformed face corner '1/'");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2 3\n"),
            "model.obj:4: malformed face corner '1//'");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3a\n"),
            "model.obj:4: malformed vertex index '3a'");
  EXPECT_EQ(errorOf("vn 0 0 nan\n"), "model.obj:1: non-finite number 'nan'");
  EXPECT_EQ(errorOf("v 0 5e43 0\n"),
            "model.obj:1: number '5e43' is out of range for single precision");
  EXPECT_EQ(errorOf("curv 0 1 2\n"), "model.obj:1: unknown statement 'curv'");
}

TEST(ObjLoaderTest, LoadsFilesAndReportsMissingOnes) {
  namespace fs = std::filesystem;
  fs::path path =
      fs::temp_directory_path() / ("lray_obj_loader_test_" + std::to_string(getpid()) + ".obj");
  std::ofstream(path, std::ios::binary) << "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
  MeshSource m = loadObj(path.string(), "tri.obj");
  EXPECT_EQ(m.faceSizes.size(), 1u);
  fs::remove(path);
  try {
    loadObj(path.string(), "tri.obj");
    FAIL();
  } catch (const SceneError &e) {
    EXPECT_STREQ(e.what(), "tri.obj: cannot open OBJ file");
  }
}

TEST(ObjLoader, DirectoriesAndDevicesAreNotObjFiles) {
  // A directory would read as an empty mesh, /dev/zero would never end.
  for (const char *path : {"/dev/zero", "/tmp"}) {
    try {
      loadObj(path, "model.obj");
      FAIL() << path;
    } catch (const SceneError &e) {
      EXPECT_EQ(std::string(e.what()), std::string("model.obj: not a regular file (") + path + ")");
    }
  }
}

} // namespace
} // namespace lray
