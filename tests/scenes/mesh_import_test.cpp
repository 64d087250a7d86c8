// glint tests — PLY and OBJ import through Assimp (scenes/mesh_import.h) and through loadScene.
#include "scenes/mesh_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene_error_support.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

size_t triangleCount(const SceneDescription& s) {
  size_t n = 0;
  for (const MeshDesc& m : s.meshes) n += m.indices.size() / 3;
  return n;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// The bunny is a benchmark mesh; a missing asset folder is a broken setup, not a reason to skip.
TEST(MeshImport, BunnyPlyMatchesTheGlbConversion) {
  std::string ply = test::assetsDir() + "/stanford/bun_zipper.ply";
  std::string glb = test::assetsDir() + "/stanford/bun_zipper.glb";
  ASSERT_TRUE(std::filesystem::exists(ply)) << ply << " missing; see benchmarks/get_assets.sh";
  ASSERT_TRUE(std::filesystem::exists(glb)) << glb << " missing; see benchmarks/get_assets.sh";

  SceneDescription fromPly = loadScene(ply);
  EXPECT_EQ(triangleCount(fromPly), 69451u);
  ASSERT_EQ(fromPly.instances.size(), fromPly.meshes.size());
  for (const InstanceDesc& inst : fromPly.instances) EXPECT_TRUE(inst.worldFromObject.isIdentity());

  SceneDescription fromGlb = loadScene(glb);
  EXPECT_EQ(triangleCount(fromGlb), 69451u);
  Bounds3f a = sceneBounds(fromPly), b = sceneBounds(fromGlb);
  ASSERT_FALSE(a.empty());
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.lower[i], b.lower[i], 1e-5) << "axis " << i;
    EXPECT_NEAR(a.upper[i], b.upper[i], 1e-5) << "axis " << i;
  }
}

TEST(MeshImport, ObjQuadsAreTriangulated) {
  std::string dir = test::scratchDir("mesh_import_obj");
  std::string path = dir + "/quads.obj";
  // Two unit quads side by side sharing an edge, with normals.
  writeFile(path,
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
            "vn 0 0 2\n"
            "f 1//1 2//1 3//1 4//1\nf 2//1 5//1 6//1 3//1\n");
  SceneDescription s;
  loadMeshFile(path, &s);
  EXPECT_EQ(triangleCount(s), 4u);
  ASSERT_EQ(s.instances.size(), s.meshes.size());
  ASSERT_FALSE(s.meshes.empty());
  Bounds3f b = sceneBounds(s);
  EXPECT_EQ(b.lower, (Vec3f{0, 0, 0}));
  EXPECT_EQ(b.upper, (Vec3f{2, 1, 0}));
  for (const MeshDesc& m : s.meshes) {
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (Vec3f n : m.normals) EXPECT_EQ(n, (Vec3f{0, 0, 1}));  // made unit length
    for (uint32_t i : m.indices) EXPECT_LT(i, m.positions.size());
  }
  EXPECT_TRUE(s.warnings.empty());
}

TEST(MeshImport, LoadSceneReadsObjFiles) {
  std::string dir = test::scratchDir("mesh_import_load_scene");
  std::string path = dir + "/tri.OBJ";  // extensions match in any case
  writeFile(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  SceneDescription s = loadScene(path);
  EXPECT_EQ(s.file, path);
  EXPECT_EQ(triangleCount(s), 1u);
  EXPECT_TRUE(s.meshes[0].normals.empty());
}

TEST(MeshImport, MalformedFileIsASceneErrorNamingTheFile) {
  std::string dir = test::scratchDir("mesh_import_malformed");
  std::string path = dir + "/broken.ply";
  writeFile(path, "not a ply file\n");
  SceneDescription s;
  EXPECT_SCENE_ERROR(errorFrom([&] { loadMeshFile(path, &s); }), path, "", "cannot read mesh");
}

// Assimp's post-processing used to crash on this (faces indexing vertices the file lacks).
TEST(MeshImport, TruncatedBinaryPlyIsASceneError) {
  std::string dir = test::scratchDir("mesh_import_truncated");
  std::string path = dir + "/truncated.ply";
  writeFile(path,
            "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\n"
            "property float y\nproperty float z\nelement face 500\n"
            "property list uchar int vertex_indices\nend_header\nabc");
  SceneDescription s;
  EXPECT_SCENE_ERROR(errorFrom([&] { loadMeshFile(path, &s); }), path, "", "cannot read mesh");
}

TEST(MeshImport, FileWithoutTrianglesIsRejected) {
  std::string dir = test::scratchDir("mesh_import_no_triangles");
  std::string path = dir + "/points.obj";
  writeFile(path, "v 0 0 0\nv 1 0 0\n");
  SceneDescription s;
  EXPECT_SCENE_ERROR(errorFrom([&] { loadMeshFile(path, &s); }), path, "", "cannot read mesh");
}

}  // namespace
}  // namespace glint
