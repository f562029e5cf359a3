/// STL files read as meshes (granular/stl_mesh.hpp): an ASCII tetrahedron and a binary cube
/// read back with their corners welded; each file of tests/meshes/bad/ refused with the file's
/// name, the triangle where one is at fault, and the reason, and nothing printed by VTK.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/stl_mesh.hpp"

using namespace granular;
namespace fs = std::filesystem;

namespace {

const fs::path kMeshes = fs::path(GRANULAR_SOURCE_DIR) / "tests" / "meshes";

struct BadMesh {
  const char* file;
  bool closed;  ///< read as a surface that must be closed
  std::vector<std::string> says;
};

const std::vector<BadMesh>& badMeshes() {
  static const std::vector<BadMesh> cases = {
      {"empty.stl", false, {"is empty"}},
      {"truncated-binary.stl", false, {"announces 12 triangles", "454 bytes", "truncated"}},
      {"wrong-count-binary.stl", false, {"announces 5 triangles", "wrong triangle count"}},
      {"short-header.stl", false, {"shorter than its 84-byte header"}},
      {"nan-vertex.stl", false, {"triangle 1", "not finite"}},
      {"zero-area.stl", false, {"triangle 4", "zero area"}},
      {"inverted-normal.stl", true, {"triangle 2", "inverted against triangle"}},
      {"open-surface.stl", true, {"triangle 0", "is open", "2 more triangles with defects: 1 2"}},
      {"non-manifold.stl", false, {"shared by 3 triangles"}},
      {"no-triangles.stl", false, {"holds no triangle"}},
      {"garbage-ascii.stl", false, {"not a readable STL file"}},
      {"zero-count-binary.stl", false, {"holds no triangle"}},
      {"duplicate-triangle.stl", false, {"triangle 0", "shared by 3 triangles"}},
  };
  return cases;
}

}  // namespace

TEST(StlMesh, AnAsciiTetrahedronAndABinaryCubeReadBackWelded) {
  const TriangleMesh tetrahedron = readStlMesh(kMeshes / "tetrahedron.stl", true);
  EXPECT_EQ(tetrahedron.vertex.size(), 4u);
  ASSERT_EQ(tetrahedron.triangle.size(), 4u);
  const TriangleMesh cube = readStlMesh(kMeshes / "cube-binary.stl", true);
  EXPECT_EQ(cube.vertex.size(), 8u);
  ASSERT_EQ(cube.triangle.size(), 12u);
  // The file's order: its first triangle is the bottom's, (0,0,0) (0,1,0) (1,1,0).
  const auto& first = cube.triangle.front();
  EXPECT_EQ(cube.vertex[first[0]], Vec3(0, 0, 0));
  EXPECT_EQ(cube.vertex[first[1]], Vec3(0, 1, 0));
  EXPECT_EQ(cube.vertex[first[2]], Vec3(1, 1, 0));
  for (const Vec3& v : cube.vertex) EXPECT_TRUE((v.array() == 0.0 || v.array() == 1.0).all());
}

TEST(StlMesh, EachBadMeshIsRefusedWithItsFileTriangleAndReasonAndVtkPrintsNothing) {
  ASSERT_GE(badMeshes().size(), 12u);
  for (const BadMesh& bad : badMeshes()) {
    const fs::path file = kMeshes / "bad" / bad.file;
    ASSERT_TRUE(fs::exists(file)) << file;
    ::testing::internal::CaptureStderr();
    std::string message;
    try {
      readStlMesh(file, bad.closed);
      ADD_FAILURE() << bad.file << " was accepted";
    } catch (const SceneError& e) {
      message = e.what();
    }
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << bad.file;
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    for (const std::string& part : bad.says) {
      EXPECT_NE(message.find(part), std::string::npos) << bad.file << ": " << message;
    }
  }
  // Every file of the corpus is in the table.
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(kMeshes / "bad"))
    files += entry.is_regular_file();
  EXPECT_EQ(files, badMeshes().size());
}

TEST(StlMesh, AMissingFileOrAFolderIsRefusedByName) {
  EXPECT_THROW(readStlMesh(kMeshes / "no-such.stl", false), IoError);
  EXPECT_THROW(readStlMesh(kMeshes, false), IoError);
}
