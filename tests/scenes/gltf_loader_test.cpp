// glint tests — glTF loading: Khronos samples in every variant, hand-made feature files, and
// one malformed input per error the loader must report with its exact location.
#include "scenes/gltf_loader.h"

#include <OpenImageIO/imageio.h>
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "image/oiio/plugin.h"
#include "materials/image_texture.h"
#include "renderer/integrator.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/gltf_container.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

// The shared assets are required: a missing folder fails (never skips) and says how to fix it.
::testing::AssertionResult assetsPresent() {
  std::string dir = test::assetsDir();
  if (fs::is_directory(dir + "/gltf") && fs::is_directory(dir + "/stanford"))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "shared asset folder '" << dir << "' (with gltf/ and stanford/) not found; set "
         << "GLINT_ASSETS to it (e.g. GLINT_ASSETS=/work/shared/assets) or configure CMake "
            "with -DGLINT_ASSETS=<folder>";
}

std::string sample(const std::string& model, const std::string& variant) {
  std::string file = model + (variant == "glTF-Binary" ? ".glb" : ".gltf");
  return test::assetsDir() + "/gltf/" + model + "/" + variant + "/" + file;
}

SceneDescription load(const std::string& path, const Transform& root = Transform()) {
  SceneDescription scene;
  loadGltf(path, &scene, root);
  return scene;
}

size_t triangleCount(const SceneDescription& s) {
  size_t n = 0;
  for (const MeshDesc& m : s.meshes) n += m.indices.size() / 3;
  return n;
}

size_t vertexCount(const SceneDescription& s) {
  size_t n = 0;
  for (const MeshDesc& m : s.meshes) n += m.positions.size();
  return n;
}

void expectNear(Vec3f actual, Vec3f expected, float tolerance = 1e-6f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

void expectBounds(const SceneDescription& s, Vec3f lower, Vec3f upper) {
  Bounds3f b = sceneBounds(s);
  expectNear(b.lower, lower);
  expectNear(b.upper, upper);
}

// Everything but file names and source locations, which differ between variants by design.
void expectSameDescription(const SceneDescription& a, const SceneDescription& b) {
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (size_t i = 0; i < a.meshes.size(); ++i) {
    const MeshDesc &x = a.meshes[i], &y = b.meshes[i];
    EXPECT_EQ(x.name, y.name);
    ASSERT_EQ(x.positions.size(), y.positions.size());
    for (size_t k = 0; k < x.positions.size(); ++k) EXPECT_EQ(x.positions[k], y.positions[k]);
    ASSERT_EQ(x.normals.size(), y.normals.size());
    for (size_t k = 0; k < x.normals.size(); ++k) EXPECT_EQ(x.normals[k], y.normals[k]);
    ASSERT_EQ(x.uvs.size(), y.uvs.size());
    for (size_t k = 0; k < x.uvs.size(); ++k) EXPECT_EQ(x.uvs[k], y.uvs[k]);
    EXPECT_EQ(x.colors.size(), y.colors.size());
    EXPECT_EQ(x.indices, y.indices);
    EXPECT_EQ(x.material, y.material);
  }
  ASSERT_EQ(a.instances.size(), b.instances.size());
  for (size_t i = 0; i < a.instances.size(); ++i) {
    EXPECT_EQ(a.instances[i].mesh, b.instances[i].mesh);
    EXPECT_EQ(a.instances[i].worldFromObject, b.instances[i].worldFromObject);
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    const MaterialDesc &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.baseColor, y.baseColor);
    EXPECT_EQ(x.opacity, y.opacity);
    EXPECT_EQ(x.baseColorTexture, y.baseColorTexture);
    EXPECT_EQ(x.metallic, y.metallic);
    EXPECT_EQ(x.roughness, y.roughness);
    EXPECT_EQ(x.emissive, y.emissive);
    EXPECT_EQ(x.doubleSided, y.doubleSided);
  }
  ASSERT_EQ(a.textures.size(), b.textures.size());
  for (size_t i = 0; i < a.textures.size(); ++i) {
    EXPECT_EQ(a.textures[i].image, b.textures[i].image);
    EXPECT_EQ(a.textures[i].wrapS, b.textures[i].wrapS);
    EXPECT_EQ(a.textures[i].nearest, b.textures[i].nearest);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (size_t i = 0; i < a.images.size(); ++i) {
    EXPECT_EQ(a.images[i].width, b.images[i].width);
    EXPECT_EQ(a.images[i].height, b.images[i].height);
    EXPECT_EQ(a.images[i].channels, b.images[i].channels);
    ASSERT_TRUE(a.images[i].encoded && b.images[i].encoded);
    EXPECT_TRUE(oiio::plugin().decodeEncodedImage(*a.images[i].encoded, nullptr) ==
                oiio::plugin().decodeEncodedImage(*b.images[i].encoded, nullptr))
        << "image " << i;
  }
  EXPECT_EQ(a.cameras.size(), b.cameras.size());
  EXPECT_EQ(a.lights.size(), b.lights.size());
}

// Loads every variant of `model`, checks they agree, and returns the first.
SceneDescription loadAllVariants(const std::string& model, std::vector<std::string> variants) {
  SceneDescription first = load(sample(model, variants[0]));
  for (size_t i = 1; i < variants.size(); ++i) {
    SCOPED_TRACE(model + " " + variants[i] + " vs " + variants[0]);
    SceneDescription other = load(sample(model, variants[i]));
    expectSameDescription(first, other);
  }
  return first;
}

const std::vector<std::string> kAllThree = {"glTF", "glTF-Embedded", "glTF-Binary"};
const std::vector<std::string> kTwo = {"glTF", "glTF-Embedded"};

// The Box samples' node 0 matrix (column-major [1,0,0,0, 0,0,-1,0, 0,1,0,0, 0,0,0,1]) maps
// (x, y, z) to (x, z, -y): the POSITION accessor's min/max of -0.5/0.5 stay a ±0.5 cube.
Mat4 boxRootMatrix() {
  const float m[16] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
  return Mat4::fromColumnMajor(m);
}

void expectBox(const SceneDescription& s) {
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(triangleCount(s), 12u);  // indices accessor count 36
  EXPECT_EQ(vertexCount(s), 24u);    // POSITION accessor count 24
  EXPECT_EQ(s.meshes[0].normals.size(), 24u);
  EXPECT_EQ(s.meshes[0].name, "Mesh");
  EXPECT_EQ(s.meshes[0].material, 0);
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.instances[0].worldFromObject.matrix(), boxRootMatrix());
  ASSERT_EQ(s.materials.size(), 1u);
  // baseColorFactor [0.8, 0, 0, 1]
  expectNear(s.materials[0].baseColor, {0.8f, 0, 0});
  EXPECT_EQ(s.materials[0].opacity, 1.0f);
  EXPECT_EQ(s.materials[0].type, MaterialType::Pbr);
  for (Vec3f n : s.meshes[0].normals) EXPECT_NEAR(length(n), 1.0f, 1e-6f);
  expectBounds(s, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
}

// ---------------------------------------------------------------------------------------------
// Khronos samples
// ---------------------------------------------------------------------------------------------

TEST(GltfLoader, LoadsBoxInAllVariants) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("Box", kAllThree);
  expectBox(s);
  EXPECT_EQ(s.materials[0].name, "Red");
  EXPECT_EQ(s.materials[0].metallic, 0.0f);   // metallicFactor 0
  EXPECT_EQ(s.materials[0].roughness, 1.0f);  // default
  EXPECT_TRUE(s.textures.empty());
  EXPECT_TRUE(s.images.empty());
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_EQ(s.meshes[0].where.pointer, "/meshes/0/primitives/0");
  EXPECT_EQ(s.instances[0].where.pointer, "/nodes/1");
}

TEST(GltfLoader, LoadsBoxInterleavedInAllVariants) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("BoxInterleaved", kAllThree);
  expectBox(s);
  // Interleaved (byteStride 24) must read the same geometry as the planar Box.
  SceneDescription box = load(sample("Box", "glTF"));
  for (size_t i = 0; i < 24; ++i) {
    EXPECT_EQ(s.meshes[0].positions[i], box.meshes[0].positions[i]) << i;
    EXPECT_EQ(s.meshes[0].normals[i], box.meshes[0].normals[i]) << i;
  }
  EXPECT_EQ(s.meshes[0].indices, box.meshes[0].indices);
}

TEST(GltfLoader, LoadsBoxTexturedInAllVariants) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("BoxTextured", kAllThree);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(triangleCount(s), 12u);
  EXPECT_EQ(s.meshes[0].uvs.size(), 24u);  // TEXCOORD_0 accessor count 24, max (6, 1)
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].baseColorTexture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].image, 0);
  EXPECT_EQ(s.textures[0].wrapS, WrapMode::Repeat);  // sampler wrapS 10497
  EXPECT_FALSE(s.textures[0].nearest);               // magFilter 9729 (LINEAR)
  ASSERT_EQ(s.images.size(), 1u);
  // CesiumLogoFlat.png: 256x256 RGBA, 8 bits (PNG IHDR).
  EXPECT_EQ(s.images[0].width, 256);
  EXPECT_EQ(s.images[0].height, 256);
  EXPECT_EQ(s.images[0].channels, 4);
  EXPECT_EQ(s.images[0].name, "CesiumLogoFlat.png");
  for (float v : oiio::plugin().decodeEncodedImage(*s.images[0].encoded, nullptr))
    ASSERT_TRUE(v >= 0 && v <= 1);
  expectBounds(s, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
  EXPECT_EQ(load(sample("BoxTextured", "glTF-Embedded")).images[0].name, "image 0");
}

TEST(GltfLoader, LoadsSimpleMeshesAsTwoInstancesOfOneMesh) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("SimpleMeshes", kTwo);
  ASSERT_EQ(s.meshes.size(), 1u);  // built once ...
  EXPECT_EQ(triangleCount(s), 1u);
  EXPECT_EQ(s.meshes[0].material, -1);  // no material: the default
  ASSERT_EQ(s.instances.size(), 2u);    // ... placed twice
  EXPECT_EQ(s.instances[0].mesh, 0);
  EXPECT_EQ(s.instances[1].mesh, 0);
  EXPECT_TRUE(s.materials.empty());
  // POSITION min (0,0,0) max (1,1,0); node 1 is translated by (1,0,0).
  expectBounds(s, {0, 0, 0}, {2, 1, 0});
}

TEST(GltfLoader, LoadsTriangleInAllVariants) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("Triangle", kTwo);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(s.instances.size(), 1u);
  EXPECT_TRUE(s.meshes[0].normals.empty());
  expectBounds(s, {0, 0, 0}, {1, 1, 0});  // POSITION min/max
}

TEST(GltfLoader, GeneratesIndicesForTriangleWithoutIndices) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("TriangleWithoutIndices", kTwo);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
  expectBounds(s, {0, 0, 0}, {1, 1, 0});
  SceneDescription indexed = load(sample("Triangle", "glTF"));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(s.meshes[0].positions[i], indexed.meshes[0].positions[i]);
}

TEST(GltfLoader, LoadsTextureCoordinateTestInAllVariants) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = loadAllVariants("TextureCoordinateTest", kTwo);
  EXPECT_EQ(s.meshes.size(), 5u);
  EXPECT_EQ(triangleCount(s), 10u);  // 5 index accessors of count 6
  EXPECT_EQ(vertexCount(s), 20u);
  EXPECT_EQ(s.instances.size(), 5u);
  EXPECT_EQ(s.materials.size(), 5u);
  EXPECT_EQ(s.textures.size(), 1u);
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].width, 512);  // TextureCoordinateTemplate.png, 512x512 RGBA
  EXPECT_EQ(s.images[0].channels, 4);
  EXPECT_EQ(s.instances[0].node, "TopLeftNode");  // RootNode's children are [5, 4, 3, 2, 1]
  EXPECT_TRUE(s.materials[0].doubleSided);
  expectNear(s.materials[1].baseColor, {0, 1, 0});  // BottomRightMaterial
  // Union of the POSITION accessors' min/max; all nodes have identity transforms.
  Bounds3f b = sceneBounds(s);
  expectNear(b.lower, {-1.200000047683716f, -1.200000047683716f, -4.3491399992490187e-07f});
  expectNear(b.upper, {1.200000047683716f, 1.200000047683716f, 0.05259101837873459f});
}

TEST(GltfLoader, LoadsStanfordBunnyGlb) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s = load(test::assetsDir() + "/stanford/bun_zipper.glb");
  EXPECT_EQ(triangleCount(s), 69451u);  // index accessor count 208353 / 3
  EXPECT_EQ(vertexCount(s), 34834u);
  EXPECT_EQ(s.instances.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_TRUE(s.materials[0].doubleSided);
  // POSITION accessor min/max.
  Bounds3f b = sceneBounds(s);
  expectNear(b.lower, {-0.09468989819288254f, 0.03298740088939667f, -0.061873599886894226f});
  expectNear(b.upper, {0.06100910156965256f, 0.1873210072517395f, 0.05879969894886017f});
}

TEST(GltfLoader, AppliesRootTransformAndAppendsToExistingScene) {
  ASSERT_TRUE(assetsPresent());
  SceneDescription s;
  loadGltf(sample("Box", "glTF"), &s);
  loadGltf(sample("Box", "glTF-Binary"), &s, Transform::translate({10, 0, 0}));
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.meshes[1].material, 1);  // offset by the materials already there
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.instances[1].mesh, 1);
  expectBounds(s, {-0.5f, -0.5f, -0.5f}, {10.5f, 0.5f, 0.5f});
}

// ---------------------------------------------------------------------------------------------
// Hand-made feature files (tests/data/gltf, regenerated by make_gltf_inputs.py)
// ---------------------------------------------------------------------------------------------

std::string goodFile(const std::string& name) { return test::dataDir() + "/gltf/" + name; }

TEST(GltfLoader, UsesDefaultSceneAndConvertsOnlyMeshesItUses) {
  SceneDescription s = load(goodFile("features.gltf"));
  // Scene 1: Strip (primitive 0; its POINTS primitive is skipped), Sparse, Fan. "Unused" is
  // only in scene 0.
  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.meshes[0].name, "Strip (primitive 0)");
  EXPECT_EQ(s.meshes[1].name, "Sparse");
  EXPECT_EQ(s.meshes[2].name, "Fan");
  ASSERT_EQ(s.instances.size(), 4u);
  EXPECT_EQ(s.instances[0].node, "StripA");
  EXPECT_EQ(s.instances[1].node, "StripB");
  EXPECT_EQ(s.instances[0].mesh, 0);
  EXPECT_EQ(s.instances[1].mesh, 0);
}

TEST(GltfLoader, TriangulatesStripsAndFans) {
  SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.meshes.size(), 3u);
  // Strip of 4: (0,1,2), then (1,3,2) to keep the winding.
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  // Fan of 5: (i+1, i+2, 0).
  EXPECT_EQ(s.meshes[2].indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
}

TEST(GltfLoader, ReadsNormalizedAttributesAndSparseAccessors) {
  SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.meshes.size(), 3u);
  const MeshDesc& strip = s.meshes[0];
  ASSERT_EQ(strip.uvs.size(), 4u);  // normalized UNSIGNED_SHORT
  EXPECT_EQ(strip.uvs[1], (Vec2f{1, 0}));
  EXPECT_EQ(strip.uvs[2], (Vec2f{0, 1}));
  ASSERT_EQ(strip.colors.size(), 4u);  // normalized UNSIGNED_BYTE VEC3: alpha 1
  EXPECT_EQ(strip.colors[0].x, 1.0f);
  EXPECT_EQ(strip.colors[0].y, 0.0f);
  EXPECT_EQ(strip.colors[2].z, 1.0f);
  EXPECT_EQ(strip.colors[1].w, 1.0f);
  const MeshDesc& sparse = s.meshes[1];
  ASSERT_EQ(sparse.positions.size(), 3u);  // zeros, with vertices 1 and 2 from `sparse`
  EXPECT_EQ(sparse.positions[0], (Vec3f{0, 0, 0}));
  EXPECT_EQ(sparse.positions[1], (Vec3f{2, 0, 0}));
  EXPECT_EQ(sparse.positions[2], (Vec3f{0, 3, 0}));
  ASSERT_EQ(sparse.normals.size(), 3u);  // stored with length 2, normalized on load
  EXPECT_EQ(sparse.normals[0], (Vec3f{0, 0, 1}));
}

TEST(GltfLoader, ComposesNodeTransforms) {
  SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.instances.size(), 4u);
  // Parent: T(10,0,0) S(2); StripA: T(0,1,0); StripB: 90 degrees about +Z.
  expectNear(s.instances[0].worldFromObject.point({0, 0, 0}), {10, 2, 0});
  expectNear(s.instances[0].worldFromObject.point({1, 1, 0}), {12, 4, 0});
  expectNear(s.instances[1].worldFromObject.point({1, 0, 0}), {10, 2, 0});
  expectNear(s.instances[1].worldFromObject.point({0, 1, 0}), {8, 0, 0});
}

TEST(GltfLoader, ReadsCamerasAndPunctualLights) {
  SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.cameras.size(), 2u);
  const CameraDesc& p = s.cameras[0];
  EXPECT_EQ(p.name, "Persp");
  EXPECT_EQ(p.type, CameraType::Perspective);
  EXPECT_FLOAT_EQ(p.yfov, 0.5f);
  EXPECT_FLOAT_EQ(p.aspectRatio, 1.5f);
  EXPECT_FLOAT_EQ(p.znear, 0.1f);
  EXPECT_FLOAT_EQ(p.zfar, 100.0f);
  expectNear(p.worldFromCamera.point({0, 0, 0}), {0, 0, 5});
  EXPECT_EQ(p.where.pointer, "/cameras/0");
  const CameraDesc& o = s.cameras[1];
  EXPECT_EQ(o.name, "OrthoNode");  // unnamed camera: the node's name
  EXPECT_EQ(o.type, CameraType::Orthographic);
  EXPECT_FLOAT_EQ(o.xmag, 2.0f);
  EXPECT_FLOAT_EQ(o.ymag, 1.0f);
  EXPECT_FLOAT_EQ(o.zfar, 50.0f);

  ASSERT_EQ(s.lights.size(), 3u);
  const LightDesc& point = s.lights[0];
  EXPECT_EQ(point.type, LightType::Point);
  EXPECT_EQ(point.name, "PointNode");
  expectNear(point.color, {1, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(point.intensity, 20.0f);
  EXPECT_FLOAT_EQ(point.range, 10.0f);
  expectNear(point.worldFromLight.point({0, 0, 0}), {0, 3, 0});
  const LightDesc& spot = s.lights[1];
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_EQ(spot.name, "Spot");
  EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.1f);
  EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.5f);
  const LightDesc& sun = s.lights[2];
  EXPECT_EQ(sun.type, LightType::Directional);
  EXPECT_EQ(sun.name, "light 2");  // neither the light nor its node is named
  EXPECT_FLOAT_EQ(sun.range, 0.0f);
  expectNear(sun.worldFromLight.point({0, 0, 0}), {1, 2, 3});  // node matrix translation
  EXPECT_EQ(sun.where.pointer, "/extensions/KHR_lights_punctual/lights/2");
}

// A sequence builds one scene per frame from the same loaded files: the second frame finds
// the first frame's images (the same encoded bytes) and decodes nothing again; a description
// whose image bytes are another buffer, even with equal contents, gets its own images.
TEST(GltfLoader, SequenceFramesShareDecodedImages) {
  const SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.images.size(), 2u);
  const RenderScene first = buildRenderScene(s);
  ASSERT_TRUE(first.images());
  const size_t held = first.images()->size();
  EXPECT_GE(held, 2u);
  const RenderScene second = buildRenderScene(s, nullptr, BuildOptions{.images = first.images()});
  EXPECT_EQ(second.images().get(), first.images().get());
  EXPECT_EQ(first.images()->size(), held);
  SceneDescription copied = s;
  for (ImageDesc& img : copied.images)
    img.encoded = std::make_shared<const std::string>(*img.encoded);
  const RenderScene third =
      buildRenderScene(copied, nullptr, BuildOptions{.images = first.images()});
  EXPECT_EQ(first.images()->size(), 2 * held);
}

TEST(GltfLoader, ReadsMaterialsTexturesSamplersAndImages) {
  SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.materials.size(), 2u);
  const MaterialDesc& m = s.materials[0];
  EXPECT_EQ(m.name, "Glowing");
  expectNear(m.baseColor, {0.5f, 0.25f, 1});
  EXPECT_FLOAT_EQ(m.opacity, 0.75f);
  EXPECT_EQ(m.baseColorTexture, 0);
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.5f);
  expectNear(m.emissive, {4, 2, 0});  // emissiveFactor x emissiveStrength 4
  EXPECT_EQ(m.emissiveTexture, 1);
  EXPECT_TRUE(m.doubleSided);
  EXPECT_EQ(s.meshes[0].material, 0);
  EXPECT_EQ(s.meshes[1].material, 1);
  const MaterialDesc& d = s.materials[1];  // "{}": glTF defaults
  expectNear(d.baseColor, {1, 1, 1});
  EXPECT_EQ(d.metallic, 1.0f);
  EXPECT_EQ(d.roughness, 1.0f);
  EXPECT_EQ(d.baseColorTexture, -1);
  EXPECT_FALSE(d.doubleSided);

  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_TRUE(s.textures[0].nearest);
  EXPECT_EQ(s.textures[0].wrapS, WrapMode::ClampToEdge);
  EXPECT_EQ(s.textures[0].wrapT, WrapMode::MirroredRepeat);
  EXPECT_EQ(s.textures[1].wrapS, WrapMode::Repeat);  // no sampler
  EXPECT_FALSE(s.textures[1].nearest);
  EXPECT_EQ(s.textures[1].image, 1);

  ASSERT_EQ(s.images.size(), 2u);
  const ImageDesc& rgb8 = s.images[0];  // 2x2 RGB, 8 bits, from a data URI
  EXPECT_EQ(rgb8.width, 2);
  EXPECT_EQ(rgb8.height, 2);
  EXPECT_EQ(rgb8.channels, 3);
  EXPECT_EQ(rgb8.bits, 8);
  EXPECT_EQ(oiio::plugin().decodeEncodedImage(*rgb8.encoded, nullptr),
            (std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(rgb8.name, "image 0");
  const ImageDesc& gray16 = s.images[1];  // 2x1 grey, 16 bits, from a bufferView
  EXPECT_EQ(gray16.width, 2);
  EXPECT_EQ(gray16.height, 1);
  EXPECT_EQ(gray16.channels, 1);
  EXPECT_EQ(gray16.bits, 16);
  EXPECT_EQ(oiio::plugin().decodeEncodedImage(*gray16.encoded, nullptr),
            (std::vector<float>{0, 1}));
}

TEST(GltfLoader, ReadsPbrExtensionsAlphaNormalMapsAndTangents) {
  SceneDescription s = load(goodFile("pbr_materials.gltf"));
  ASSERT_EQ(s.materials.size(), 1u);
  const MaterialDesc& m = s.materials[0];
  EXPECT_EQ(m.type, MaterialType::Pbr);
  EXPECT_EQ(m.metallicRoughnessTexture, 0);
  EXPECT_EQ(m.normalTexture, 0);
  EXPECT_FLOAT_EQ(m.normalScale, 0.5f);
  EXPECT_EQ(m.alphaMode, AlphaModeDesc::Mask);
  EXPECT_FLOAT_EQ(m.alphaCutoff, 0.3f);
  EXPECT_FLOAT_EQ(m.transmission, 0.8f);
  EXPECT_EQ(m.transmissionTexture, 0);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].tangents.size(), 3u);
  for (const Vec4f& t : s.meshes[0].tangents) {  // normalized, handedness kept
    EXPECT_FLOAT_EQ(t.x, 1);
    EXPECT_FLOAT_EQ(t.w, -1);
  }
  // Built: the tangent reaches the surface interaction of a hit that needs tangents.
  RenderScene scene = buildRenderScene(s);
  EXPECT_TRUE(scene.features().has(Feature::Bump));
  EXPECT_TRUE(scene.features().has(Feature::Refraction));
  EXPECT_TRUE(scene.features().has(Feature::Transparency));
  EXPECT_TRUE(scene.features().has(Feature::Textures));
  Ray ray{{0.25f, 0.25f, 1}, {0, 0, -1}};
  Hit hit;
  ASSERT_TRUE(scene.accel().closestHit(ray, &hit));
  SurfaceInteraction si =
      computeSurfaceInteraction(scene.geometry(), ray, hit, {.uvs = true, .tangents = true});
  EXPECT_NEAR(si.tangent.x, 1, 1e-6f);
  EXPECT_EQ(si.bitangentSign, -1.0f);
  EXPECT_NEAR(length(si.dpdu - Vec3f{1, 0, 0}), 0, 1e-6f);  // from the UVs
}

TEST(GltfLoader, WarnsAboutSkippedPrimitivesAndOtherTexCoordSets) {
  SceneDescription s = load(goodFile("features.gltf"));
  ASSERT_EQ(s.warnings.size(), 3u);
  std::string all = s.warnings[0] + "\n" + s.warnings[1] + "\n" + s.warnings[2];
  EXPECT_NE(all.find("/extensionsUsed/2: extension 'EXT_unknown_optional' is not supported"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("/materials/0/pbrMetallicRoughness/baseColorTexture/texCoord: texCoord 2 is "
                     "not supported (glint reads TEXCOORD_0 and TEXCOORD_1)"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("/meshes/0/primitives/1: POINTS primitive skipped"), std::string::npos) << all;
}

TEST(GltfLoader, LoadsAllRootNodesWhenThereAreNoScenes) {
  for (const char* name : {"no_scenes.gltf", "no_scenes.glb"}) {
    SCOPED_TRACE(name);
    SceneDescription s = load(goodFile(name));
    EXPECT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.instances.size(), 3u);  // roots 0 and 1, and node 2 under node 0
    expectBounds(s, {0, 0, -1}, {1, 1, 1});
  }
}

// ---------------------------------------------------------------------------------------------
// Malformed inputs (tests/data/bad, see its README.md)
// ---------------------------------------------------------------------------------------------

std::string badFile(const std::string& name) { return test::dataDir() + "/bad/" + name; }

// Loads `file`, expecting a SceneError at `pointer` of `file` whose message contains `phrase`.
void expectError(const std::string& file, const std::string& pointer, const std::string& phrase,
                 const std::string& reportedFile = "") {
  SceneDescription scene;
  try {
    loadGltf(file, &scene);
    ADD_FAILURE() << file << " loaded without error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.where().file, reportedFile.empty() ? file : reportedFile) << e.what();
    EXPECT_EQ(e.where().pointer, pointer) << e.what();
    EXPECT_NE(e.message().find(phrase), std::string::npos)
        << "message '" << e.message() << "' lacks '" << phrase << "'";
  }
}

TEST(GltfBadInput, MissingFileIsRejected) {
  expectError(badFile("does_not_exist.gltf"), "", "cannot open file");
}

TEST(GltfBadInput, TruncatedGlbIsRejected) {
  // make_bad_inputs.py cuts a 592-byte GLB to 100 bytes.
  expectError(badFile("truncated.glb"), "", "truncated GLB: header says 592 bytes, file has 100");
}

TEST(GltfBadInput, AccessorOutOfBoundsIsRejected) {
  expectError(badFile("accessor_out_of_bounds.gltf"), "/accessors/1",
              "needs bytes 0..48 but bufferView 1 has only 36 bytes");
}

TEST(GltfBadInput, BufferViewOutOfBoundsIsRejected) {
  expectError(badFile("buffer_view_out_of_bounds.gltf"), "/bufferViews/1",
              "bytes 8..56 lie outside buffer 0 (44 bytes)");
}

TEST(GltfBadInput, MissingBinIsRejected) {
  expectError(badFile("missing_bin.gltf"), "/buffers/0/uri", "cannot read 'missing_bin.bin'");
}

TEST(GltfBadInput, ShortBinIsRejected) {
  expectError(badFile("bin_too_short.gltf"), "/buffers/0/byteLength",
              "byteLength is 44 but 'bin_too_short.bin' has 40 bytes");
}

TEST(GltfBadInput, IndexOutOfRangeIsRejected) {
  expectError(badFile("index_out_of_range.gltf"), "/meshes/0/primitives/0/indices",
              "index 57 out of range (3 vertices)");
}

TEST(GltfBadInput, NanPositionsAreRejected) {
  expectError(badFile("nan_positions.gltf"), "/accessors/1", "position 2 is not finite");
}

TEST(GltfBadInput, InfPositionsAreRejected) {
  expectError(badFile("inf_positions.gltf"), "/accessors/1", "position 1 is not finite");
}

TEST(GltfBadInput, ZeroLengthNormalsAreRejected) {
  expectError(badFile("zero_length_normals.gltf"), "/accessors/2", "normal 2 has zero length");
}

TEST(GltfBadInput, CameraZnearNotBelowZfarIsRejected) {
  expectError(badFile("camera_znear_ge_zfar.gltf"), "/cameras/0/perspective/zfar",
              "must be greater than znear");
}

TEST(GltfBadInput, BufferUriOutsideSceneFolderIsRejected) {
  expectError(badFile("buffer_uri_outside_folder.gltf"), "/buffers/0/uri",
              "'../outside.bin' leaves the scene folder");
}

TEST(GltfBadInput, AbsoluteBufferUriIsRejected) {
  expectError(badFile("absolute_uri.gltf"), "/buffers/0/uri",
              "'/etc/hostname' leaves the scene folder");
}

TEST(GltfBadInput, JsonSyntaxErrorReportsLineAndColumn) {
  // The second node object on line 5 starts at column 5 without a comma before it.
  std::string file = badFile("json_syntax_error.gltf");
  expectError(file, "", "JSON syntax error", file + ":5:5");
}

TEST(GltfBadInput, WrongTypeIsRejected) {
  expectError(badFile("wrong_type.gltf"), "/accessors/1/count",
              "expected a non-negative integer, got string \"three\"");
}

TEST(GltfBadInput, UnsupportedRequiredExtensionIsRejected) {
  expectError(badFile("unsupported_required_extension.gltf"), "/extensionsRequired/0",
              "unsupported extension 'KHR_materials_pbrSpecularGlossiness'");
}

TEST(GltfBadInput, RequiredExtensionErrorListsWhatGlintSupports) {
  try {
    load(badFile("unsupported_required_extension.gltf"));
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("glint supports KHR_lights_punctual"), std::string::npos)
        << e.what();
  }
}

TEST(GltfLoader, WarnsAboutExtensionsItUsesButGlintIgnores) {
  std::ifstream in(badFile("unsupported_required_extension.gltf"));
  nlohmann::json j = nlohmann::json::parse(in);
  j.erase("extensionsRequired");
  j["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness", "KHR_lights_punctual",
                         "VENDOR_thing"};
  const std::string path = test::scratchDir("gltf_extensions_used") + "/used.gltf";
  std::ofstream(path) << j.dump();
  SceneDescription s = load(path);
  ASSERT_EQ(s.warnings.size(), 2u);  // the supported one is not mentioned
  EXPECT_NE(s.warnings[0].find("/extensionsUsed/0: extension "
                               "'KHR_materials_pbrSpecularGlossiness' is not supported; ignored: "
                               "the metallic-roughness parameters, if any"),
            std::string::npos)
      << s.warnings[0];
  EXPECT_NE(s.warnings[1].find("/extensionsUsed/2: extension 'VENDOR_thing'"), std::string::npos)
      << s.warnings[1];
}

// Every ratified material extension is read into the material's description, and builds.
TEST(GltfLoader, MaterialExtensionsAreRead) {
  SceneDescription s = load(goodFile("material_layers.gltf"));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
  ASSERT_EQ(s.materials.size(), 2u);
  const MaterialDesc& volume = s.materials[0];
  EXPECT_FALSE(volume.thinWalled);
  EXPECT_FLOAT_EQ(volume.layers.thickness, 2);
  EXPECT_EQ(volume.layers.attenuationColor, (Rgb{0.5f, 0.25f, 0.8f}));
  EXPECT_FLOAT_EQ(volume.layers.attenuationDistance, 1);
  EXPECT_FLOAT_EQ(volume.ior, 1);
  const MaterialDesc& m = s.materials[1];
  EXPECT_TRUE(m.thinWalled);  // no volume: a thin sheet
  const MaterialLayersDesc& l = m.layers;
  EXPECT_FLOAT_EQ(l.specular, 0.5f);
  EXPECT_EQ(l.specularColor, (Rgb{1, 0.5f, 2}));
  EXPECT_FLOAT_EQ(l.clearcoat, 0.75f);
  EXPECT_FLOAT_EQ(l.clearcoatRoughness, 0.125f);
  EXPECT_EQ(l.sheenColor, (Rgb{0.25f, 0.5f, 0.75f}));
  EXPECT_FLOAT_EQ(l.sheenRoughness, 0.375f);
  EXPECT_FLOAT_EQ(l.diffuseTransmission, 0.25f);
  EXPECT_EQ(l.diffuseTransmissionColor, (Rgb{1, 0.75f, 0.5f}));
  EXPECT_FLOAT_EQ(l.iridescence, 1);
  EXPECT_FLOAT_EQ(l.iridescenceIor, 1.75f);
  EXPECT_FLOAT_EQ(l.iridescenceThicknessMin, 50);
  EXPECT_FLOAT_EQ(l.iridescenceThicknessMax, 500);
  EXPECT_FLOAT_EQ(l.anisotropy, 0.5f);
  EXPECT_FLOAT_EQ(l.anisotropyRotation, 1.5f);
  EXPECT_FLOAT_EQ(l.dispersion, 0.5f);
  RenderScene scene = buildRenderScene(s);
  ASSERT_EQ(scene.materials().size(), 2u);
  EXPECT_GT(maxComponent(scene.materials()[0]->absorption()), 0);
  EXPECT_EQ(scene.materials()[1]->absorption(), (Rgb{0, 0, 0}));
  EXPECT_TRUE(scene.materials()[1]->traits().needs.tangents);  // anisotropy reads the tangent
}

TEST(GltfBadInput, MaterialExtensionsOutOfRangeAreRejected) {
  const std::string ext = "/materials/1/extensions/";
  expectError(badFile("clearcoat_factor_above_one.gltf"),
              ext + "KHR_materials_clearcoat/clearcoatFactor", "must be between 0 and 1");
  expectError(badFile("sheen_color_negative.gltf"), ext + "KHR_materials_sheen/sheenColorFactor/0",
              "must not be negative");
  expectError(badFile("iridescence_ior_below_one.gltf"),
              ext + "KHR_materials_iridescence/iridescenceIor", "must be >= 1");
  expectError(badFile("volume_attenuation_distance_zero.gltf"),
              "/materials/0/extensions/KHR_materials_volume/attenuationDistance", "must be > 0");
}

TEST(GltfLoader, TextureTransformsBecomeTextureMappings) {
  std::ifstream in(goodFile("features.gltf"));
  nlohmann::json j = nlohmann::json::parse(in);
  const nlohmann::json transform = {{"offset", {0.5, 0}}, {"rotation", 0.3}, {"scale", {2, 4}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
      {"KHR_texture_transform", transform}};
  j["materials"][0]["emissiveTexture"]["extensions"] = {{"KHR_texture_transform", transform}};
  j["extensionsUsed"].push_back("KHR_texture_transform");
  const std::string dir = test::scratchDir("gltf_texture_transform");
  std::ofstream(dir + "/t.gltf") << j.dump();
  SceneDescription s = load(dir + "/t.gltf");
  const MaterialDesc& m = s.materials[0];
  ASSERT_GE(m.baseColorTexture, 0);
  const TextureDesc& t = s.textures[size_t(m.baseColorTexture)];
  EXPECT_EQ(t.mapping.scale, (Vec3f{2, 4, 1}));
  EXPECT_EQ(t.mapping.offset, (Vec3f{0.5f, 0, 0}));
  EXPECT_FLOAT_EQ(t.mapping.uvRotation, 0.3f);
  // A copy of the file's texture (same image), made once per distinct transform: the emissive
  // texture is another texture of the file, so it gets its own copy.
  EXPECT_EQ(s.textures.size(), 4u);
  EXPECT_EQ(t.image, s.textures[0].image);
  EXPECT_NE(m.emissiveTexture, m.baseColorTexture);
  EXPECT_EQ(s.textures[size_t(m.emissiveTexture)].mapping.uvRotation, 0.3f);
  // No warning for the extension now.
  for (const std::string& w : s.warnings)
    EXPECT_EQ(w.find("KHR_texture_transform"), std::string::npos) << w;
  // Bad values name the pointer.
  j["materials"][0]["emissiveTexture"]["extensions"]["KHR_texture_transform"]["scale"] = {1};
  std::ofstream(dir + "/bad.gltf") << j.dump();
  expectError(dir + "/bad.gltf",
              "/materials/0/emissiveTexture/extensions/KHR_texture_transform/scale",
              "expected an array of 2 numbers");
}

TEST(GltfBadInput, TextureTransformWithANonNumberIsRejected) {
  expectError(badFile("texture_transform_nan_scale.gltf"),
              "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/"
              "KHR_texture_transform/scale/1",
              "expected a number, got string");
}

TEST(GltfBadInput, SkinsAndMorphTargetsThatDisagreeAreRejected) {
  expectError(badFile("skin_joint_out_of_range.gltf"), "/meshes/1/primitives/0/attributes/JOINTS_0",
              "vertex 1 names joint 1 but skin 0 (/nodes/3/skin) has 1 joints");
  expectError(badFile("skin_index_out_of_range.gltf"), "/nodes/3/skin",
              "skin 2 does not exist (1 skin in the file)");
  expectError(badFile("morph_weights_count_mismatch.gltf"), "/meshes/0/weights",
              "has 3 weights but the mesh's primitives have 2 morph targets");
  expectError(badFile("morph_target_count_mismatch.gltf"), "/meshes/0/primitives/1/targets",
              "has 1 morph target but primitive 0 has 2");
  expectError(badFile("morph_animation_output_count.gltf"), "/animations/0/samplers/0/output",
              "with 2 keys and 2 morph targets needs 4");
}

TEST(GltfLoader, QuantizedAttributesAndGpuInstancesAreRead) {
  SceneDescription s = load(goodFile("instanced_quantized.gltf"));
  EXPECT_TRUE(s.warnings.empty());
  ASSERT_EQ(s.meshes.size(), 1u);
  const MeshDesc& m = s.meshes[0];
  // UNSIGNED_SHORT positions, not normalized: the node's scale 1/65535 dequantizes them.
  EXPECT_EQ(m.positions[1], (Vec3f{65535, 0, 0}));
  ASSERT_EQ(s.instances.size(), 4u);  // the plain node, then three GPU instances
  expectNear(s.instances[0].worldFromObject.point(m.positions[1]), {1, 0, 0}, 1e-6f);
  // Normalized BYTE normals and SHORT texture coordinates.
  expectNear(m.normals[0], {0, 0, 1});
  EXPECT_NEAR(m.uvs[1].x, 1, 1e-6f);
  EXPECT_NEAR(m.uvs[2].y, 1, 1e-6f);
  // Instance k: node (translate (0,0,-1), scale 1/65535) x T_k R_k S_k.
  expectNear(s.instances[1].worldFromObject.point(m.positions[1]), {1, 0, -1}, 1e-5f);
  // 90 degrees about z (normalized SHORT): +x goes to +y.
  expectNear(s.instances[2].worldFromObject.point(m.positions[1]), {2 / 65535.0f, 1, -1}, 1e-4f);
  expectNear(s.instances[3].worldFromObject.point(m.positions[1]), {4 / 65535.0f + 2, 0, -1},
             1e-4f);
  // They share the mesh: built, it is stored once and instanced.
  RenderScene scene = buildRenderScene(s);
  EXPECT_EQ(scene.geometry().instances.size(), 4u);
  EXPECT_EQ(scene.geometry().uniqueTriangleCount(), 1u);
  EXPECT_EQ(scene.geometry().instancedTriangleCount(), 4u);
}

TEST(GltfBadInput, QuantizationAndInstancingAreChecked) {
  expectError(badFile("quantized_without_extension.gltf"),
              "/meshes/0/primitives/0/attributes/POSITION",
              "other types need KHR_mesh_quantization");
  expectError(badFile("instancing_count_mismatch.gltf"),
              "/nodes/1/extensions/EXT_mesh_gpu_instancing/attributes/SCALE",
              "has 2 elements but the other instancing attributes have 3");
}

TEST(GltfLoader, MaterialVariantsChooseEachPrimitivesMaterial) {
  SceneDescription s = load(goodFile("variants.gltf"));
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_EQ(s.variants, (std::vector<std::string>{"blue", "green", "lime"}));
  // Unlit materials: every pixel is the chosen material's colour exactly.
  auto colourOf = [&](const std::string& variant) {
    SceneDescription d = s;
    d.render.variant = variant;
    d.render.width = d.render.height = 4;
    d.render.spp = 1;
    RenderScene scene = buildRenderScene(d);
    auto integrator = makeIntegrator(scene, d.render);
    RenderStats stats;
    const Film film = render(scene, *integrator, d.render, {.threads = 1}, &stats);
    return film.color[5];
  };
  expectNear(colourOf(""), {0.8f, 0, 0});
  expectNear(colourOf("blue"), {0, 0, 0.8f});
  expectNear(colourOf("green"), {0, 0.8f, 0});
  expectNear(colourOf("lime"), {0, 0.8f, 0});
  SceneDescription unknown = s;
  unknown.render.variant = "purple";
  SceneError e = test::errorFrom([&] { buildRenderScene(unknown); });
  EXPECT_NE(e.message().find("variants: 'blue', 'green', 'lime'"), std::string::npos) << e.what();
  expectError(badFile("variant_index_out_of_range.gltf"),
              "/meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/1/variants/1",
              "variant 5 does not exist (3 variants in the file)");
}

TEST(GltfLoader, UnlitMaterialsKeepTheirBaseColour) {
  std::ifstream in(goodFile("features.gltf"));
  nlohmann::json j = nlohmann::json::parse(in);
  j["materials"][0]["extensions"]["KHR_materials_unlit"] = nlohmann::json::object();
  j["extensionsUsed"].push_back("KHR_materials_unlit");
  const std::string path = test::scratchDir("gltf_unlit") + "/unlit.gltf";
  std::ofstream(path) << j.dump();
  SceneDescription s = load(path);
  EXPECT_EQ(s.materials[0].type, MaterialType::Unlit);
  EXPECT_EQ(s.materials[0].baseColor, (Rgb{0.5f, 0.25f, 1}));
  EXPECT_GE(s.materials[0].baseColorTexture, 0);
  EXPECT_EQ(s.materials[1].type, MaterialType::Pbr);
  for (const std::string& w : s.warnings)
    EXPECT_EQ(w.find("KHR_materials_unlit"), std::string::npos) << w;
}

TEST(GltfBadInput, BasisUniversalTextureWithoutFallbackIsRejected) {
  std::ifstream in(badFile("texture_transform_nan_scale.gltf"));
  nlohmann::json j = nlohmann::json::parse(in);
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].erase("extensions");
  j["textures"][0].erase("source");
  j["textures"][0]["extensions"] = {{"KHR_texture_basisu", {{"source", 0}}}};
  j["extensionsUsed"] = {"KHR_texture_basisu"};
  const std::string path = test::scratchDir("gltf_basisu") + "/basisu.gltf";
  std::ofstream(path) << j.dump();
  expectError(path, "/textures/0/extensions/KHR_texture_basisu", "Basis Universal");
}

TEST(GltfBadInput, NodeCycleIsRejected) {
  expectError(badFile("node_cycle.gltf"), "/nodes/1/children/0",
              "node 0 is an ancestor of node 1 (cycle in the node graph)");
}

// A chain of `n` nodes, each the only child of the one before; `closed`: the last node's child
// is node 0, so the chain is one long cycle with no root.
std::string nodeChain(size_t n, bool closed = false) {
  nlohmann::json nodes = nlohmann::json::array();
  for (size_t i = 0; i < n; ++i) {
    nlohmann::json node = nlohmann::json::object();
    if (i + 1 < n || closed) node["children"] = {(i + 1) % n};
    nodes.push_back(node);
  }
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}}, {"nodes", nodes}};
  if (!closed) doc["scenes"] = {{{"nodes", {0}}}};
  return doc.dump();
}

TEST(GltfBadInput, NodeHierarchyDeeperThanTheLimitIsRejected) {
  // Found while fuzzing the loaders (issue 8): a chain of 200 000 nodes ran for minutes in the
  // cycle check (quadratic in the depth) and would then have overflowed the stack in the
  // recursive walk that instances the nodes. Now the check is linear and stops at the limit.
  SceneDescription scene;
  SceneError e =
      test::errorFrom([&] { loadGltfFromMemory(nodeChain(100000), "chain.gltf", &scene); });
  EXPECT_SCENE_ERROR(e, "chain.gltf", "/nodes/1000/children/0",
                     "node 1001 is nested 1001 levels below its root node; glint reads node "
                     "hierarchies at most 1000 levels deep");
  EXPECT_TRUE(scene.nodes.empty() && scene.instances.empty());
}

TEST(GltfBadInput, LongNodeCycleIsRejected) {
  SceneDescription scene;
  SceneError e =
      test::errorFrom([&] { loadGltfFromMemory(nodeChain(5000, true), "cycle.gltf", &scene); });
  EXPECT_SCENE_ERROR(e, "cycle.gltf", "/nodes/4999/children/0",
                     "node 0 is an ancestor of node 4999 (cycle in the node graph)");
}

TEST(GltfLoader, NodeHierarchyAtTheDepthLimitLoads) {
  SceneDescription scene;
  EXPECT_NO_THROW(loadGltfFromMemory(nodeChain(1001), "chain.gltf", &scene));  // levels 0..1000
}

TEST(GltfLoader, LoadsFromMemoryLikeFromTheFile) {
  std::string file = goodFile("no_scenes.glb");
  SceneDescription fromFile, fromMemory;
  loadGltf(file, &fromFile);
  loadGltfFromMemory(test::slurp(file), file, &fromMemory);
  ASSERT_FALSE(fromFile.meshes.empty());
  expectSameDescription(fromFile, fromMemory);
}

TEST(GltfBadInput, SingularNodeMatrixIsRejected) {
  expectError(badFile("singular_matrix.gltf"), "/nodes/0/matrix", "matrix is not invertible");
}

TEST(GltfBadInput, MaterialIndexOutOfRangeIsRejected) {
  expectError(badFile("material_index_out_of_range.gltf"), "/meshes/0/primitives/0/material",
              "material 3 does not exist (0 materials in the file)");
}

TEST(GltfBadInput, FailedLoadLeavesSceneUntouched) {
  SceneDescription scene;
  loadGltf(goodFile("no_scenes.gltf"), &scene);
  size_t meshes = scene.meshes.size(), instances = scene.instances.size();
  // The index check runs while meshes are being converted, after instancing has begun.
  EXPECT_THROW(loadGltf(badFile("index_out_of_range.gltf"), &scene), SceneError);
  EXPECT_EQ(scene.meshes.size(), meshes);
  EXPECT_EQ(scene.instances.size(), instances);
  EXPECT_TRUE(scene.warnings.empty());
}

std::string base64(const std::string& bytes) {
  static const char* kB64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) n |= uint8_t(bytes[i + 2]);
    b64 += kB64[(n >> 18) & 63];
    b64 += kB64[(n >> 12) & 63];
    b64 += i + 1 < bytes.size() ? kB64[(n >> 6) & 63] : '=';
    b64 += i + 2 < bytes.size() ? kB64[n & 63] : '=';
  }
  return b64;
}

// A glTF embedding `png` as a data URI.
std::string gltfWithEmbeddedPng(const std::string& png) {
  return R"({"asset": {"version": "2.0"}, "images": [{"uri": "data:image/png;base64,)" +
         base64(png) + R"("}], "scenes": [{"nodes": []}], "scene": 0})";
}

// A PNG signature and IHDR chunk of the given size, then one chunk whose length field says
// `nextChunkLength` (its data absent).
std::string pngHeader(uint32_t width, uint32_t height, uint32_t nextChunkLength) {
  std::string png = "\x89PNG\r\n\x1a\n";
  auto be32 = [&](uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) png += char((v >> shift) & 0xff);
  };
  be32(13);
  png += "IHDR";
  be32(width);
  be32(height);
  png += std::string("\x08\x06\0\0\0", 5);
  be32(0);  // CRC (stb_image does not check it)
  be32(nextChunkLength);
  png += "IDAT";
  return png;
}

// Embedded images that would make stb_image allocate gigabytes from a few bytes (found by
// fuzzing, tests/fuzz) are refused before decoding: a header claiming 60000 x 60000 pixels,
// and a 2 x 2 image with a chunk claiming 512 MB.
TEST(GltfLoader, RefusesImagesThatClaimMoreThanTheyHold) {
  SceneDescription scene;
  SceneError huge = test::errorFrom([&] {
    loadGltfFromMemory(gltfWithEmbeddedPng(pngHeader(60000, 60000, 0)), "a.gltf", &scene);
  });
  EXPECT_NE(huge.message().find("60000 x 60000"), std::string::npos) << huge.what();
  SceneError chunk = test::errorFrom([&] {
    loadGltfFromMemory(gltfWithEmbeddedPng(pngHeader(2, 2, 536870930)), "b.gltf", &scene);
  });
  EXPECT_NE(chunk.message().find("claims 536870930 bytes"), std::string::npos) << chunk.what();
}

// A glTF of one square in its z = 0 plane, wound counter-clockwise seen from +z (its front),
// under a node of scale `scale`, with one material (`materialJson`, a glTF material object).
std::string squareGltf(const std::string& materialJson, Vec3f scale) {
  const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const uint16_t indices[] = {0, 1, 2, 0, 2, 3};
  std::string bytes(reinterpret_cast<const char*>(positions), sizeof(positions));
  bytes += std::string(reinterpret_cast<const char*>(indices), sizeof(indices));
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"buffers",
       {{{"byteLength", bytes.size()},
         {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", sizeof(positions)}},
        {{"buffer", 0}, {"byteOffset", sizeof(positions)}, {"byteLength", sizeof(indices)}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 4},
         {"type", "VEC3"},
         {"min", {-1, -1, 0}},
         {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
      {"materials", {nlohmann::json::parse(materialJson)}},
      {"meshes",
       {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}}}},
      {"nodes", {{{"mesh", 0}, {"scale", {scale.x, scale.y, scale.z}}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  return j.dump();
}

TEST(GltfLoader, SingleSidedMaterialsHideBackFacesOnceBuilt) {
  const std::string dir = test::scratchDir("GltfLoader.SingleSided");
  struct Case {
    const char* what;
    std::string material;
    Vec3f scale;
    bool backVisible;
    float frontZ;  // the side the front faces after the node's scale
  };
  const Case cases[] = {
      {"glTF default: single-sided", R"({})", {1, 1, 1}, false, 1},
      {"doubleSided", R"({"doubleSided": true})", {1, 1, 1}, true, 1},
      // A mirror across the plane turns the front over (the determinant rule); one within the
      // plane does not.
      {"mirrored across", R"({})", {1, 1, -1}, false, -1},
      {"mirrored within", R"({})", {-1, 1, 1}, false, 1},
      // Light must leave a transmissive surface through its back.
      {"transmissive",
       R"({"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}})",
       {1, 1, 1},
       true,
       1},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string path = dir + "/square.gltf";
    std::ofstream(path) << squareGltf(c.material, c.scale);
    SceneDescription d = loadScene(path);
    RenderScene scene = buildRenderScene(d);
    const Ray fromFront{{0.1f, 0.2f, 5 * c.frontZ}, {0, 0, -c.frontZ}, 0, kInfinity, 0};
    const Ray fromBack{{0.1f, 0.2f, -5 * c.frontZ}, {0, 0, c.frontZ}, 0, kInfinity, 0};
    Hit h;
    EXPECT_TRUE(scene.accel().closestHit(fromFront, &h));
    EXPECT_EQ(scene.accel().closestHit(fromBack, &h), c.backVisible);
    EXPECT_EQ(scene.accel().anyHit(fromBack), c.backVisible);
  }
  // A single-sided emitter is a one-sided light: nothing behind it is lit.
  std::ofstream(dir + "/square.gltf") << squareGltf(R"({"emissiveFactor": [1, 1, 1]})", {1, 1, 1});
  SceneDescription d = loadScene(dir + "/square.gltf");
  RenderScene scene = buildRenderScene(d);
  ASSERT_FALSE(scene.instanceLight().empty());
  const Light& light = *scene.lights()[size_t(scene.instanceLight()[0])];
  LightSampleContext front, back;
  front.p = {0, 0, 2};
  back.p = {0, 0, -2};
  auto lit = [&](const LightSampleContext& ctx) {
    auto s = light.sampleLi(ctx, {0.3f, 0.6f});
    return s && maxComponent(s->L) > 0;
  };
  EXPECT_TRUE(lit(front));
  EXPECT_FALSE(lit(back));
}

// The bytes of a w x h RGB image file written by OpenImageIO (format from the extension): of
// one colour, or of noise.
std::string imageFileBytes(const std::string& path, int w, int h, std::vector<unsigned char> rgb,
                           bool noise = false) {
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeUInt8);
  if (!out || !out->open(path, spec)) throw std::runtime_error("cannot write " + path);
  std::vector<unsigned char> px;
  for (int i = 0; i < w * h; ++i)
    for (int c = 0; c < 3; ++c)
      px.push_back(noise ? static_cast<unsigned char>((i * 37 + c * 101) & 255) : rgb[size_t(c)]);
  out->write_image(OIIO::TypeUInt8, px.data());
  out->close();
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(GltfLoader, WebpTexturesAreDecodedAndWinOverTheFallback) {
  // A 4x4 WebP of one colour beside a PNG fallback of another, written by OpenImageIO.
  const std::string dir = test::scratchDir("GltfLoader.Webp");
  imageFileBytes(dir + "/c.webp", 4, 4, {200, 100, 50});
  const std::string png = imageFileBytes(dir + "/c.png", 4, 4, {0, 255, 0});
  nlohmann::json j = nlohmann::json::parse(gltfWithEmbeddedPng(png));
  j["images"].push_back({{"uri", "c.webp"}});
  j["textures"] = {{{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}}};
  j["extensionsUsed"] = {"EXT_texture_webp"};
  const std::string path = dir + "/webp.gltf";
  std::ofstream(path) << j.dump();
  SceneDescription s = load(path);
  EXPECT_TRUE(s.warnings.empty());
  ASSERT_EQ(s.textures.size(), 1u);
  const ImageDesc& image = s.images[size_t(s.textures[0].image)];
  EXPECT_EQ(image.width, 4);
  EXPECT_EQ(image.channels, 3);
  const std::vector<float> px = oiio::plugin().decodeEncodedImage(*image.encoded, nullptr);
  EXPECT_NEAR(px[0], 200 / 255.0f, 3 / 255.0f);
  EXPECT_NEAR(px[1], 100 / 255.0f, 3 / 255.0f);
  EXPECT_NEAR(px[2], 50 / 255.0f, 3 / 255.0f);
}

TEST(GltfLoader, ImagesInDataUrisOfAnyFormatOpenImageIOReads) {
  // A WebP as a data URI: glint reads data URIs itself and OpenImageIO decodes whatever they
  // hold (tinygltf 2.7, which glint used before, took PNG and JPEG only).
  const std::string dir = test::scratchDir("GltfLoader.WebpDataUri");
  const std::string webp = imageFileBytes(dir + "/c.webp", 4, 4, {200, 100, 50});
  nlohmann::json j = nlohmann::json::parse(gltfWithEmbeddedPng(webp));
  j["images"][0]["uri"] = "data:image/webp;base64," + base64(webp);
  SceneDescription s;
  loadGltfFromMemory(j.dump(), dir + "/webp.gltf", &s);
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].width, 4);
  EXPECT_EQ(*s.images[0].encoded, webp);
}

TEST(GltfContainer, DecodesBase64DataUris) {
  std::string bytes;
  ASSERT_TRUE(gltf::decodeDataUri("data:application/octet-stream;base64,AAEC/w==", &bytes));
  EXPECT_EQ(bytes, std::string("\x00\x01\x02\xff", 4));
  // Padding may be left out; any media type is read (the bytes say what they are).
  ASSERT_TRUE(gltf::decodeDataUri("data:application/gltf-buffer;base64,AAEC/w", &bytes));
  EXPECT_EQ(bytes, std::string("\x00\x01\x02\xff", 4));
  ASSERT_TRUE(gltf::decodeDataUri("data:;base64,TWFu", &bytes));
  EXPECT_EQ(bytes, "Man");
  ASSERT_TRUE(gltf::decodeDataUri("data:image/png;base64,", &bytes));
  EXPECT_EQ(bytes, "");
  // Every base64 digit, in order: 48 bytes that encode 0..63 as 6-bit groups.
  std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  ASSERT_TRUE(gltf::decodeDataUri("data:;base64," + digits, &bytes));
  ASSERT_EQ(bytes.size(), 48u);
  EXPECT_EQ(base64(bytes), digits);
  // Not base64, or not base64 glint reads: refused, never read as something else.
  for (const char* bad :
       {"data:text/plain,hello", "data:;base64,TW=u", "data:;base64,TW-u",
        "data:;base64,TQ===", "data:;base64,TWF u", "data:;base64", "file:x.bin", "data:;base64,T"})
    EXPECT_FALSE(gltf::decodeDataUri(bad, &bytes)) << bad;
}

TEST(GltfBadInput, BufferDataUriThatIsNotBase64IsRejectedAtItsUri) {
  nlohmann::json j = nlohmann::json::parse(squareGltf("{}", {1, 1, 1}));
  j["buffers"][0]["uri"] = "data:application/octet-stream;base64,AA!A";
  SceneDescription scene;
  SceneError e = test::errorFrom([&] { loadGltfFromMemory(j.dump(), "uri.gltf", &scene); });
  EXPECT_EQ(e.where().pointer, "/buffers/0/uri");
  EXPECT_NE(e.message().find("cannot decode the data URI"), std::string::npos) << e.what();
  j["buffers"][0]["uri"] = "data:application/octet-stream;base64,AAAA";
  e = test::errorFrom([&] { loadGltfFromMemory(j.dump(), "uri.gltf", &scene); });
  EXPECT_EQ(e.where().pointer, "/buffers/0/byteLength");
  EXPECT_NE(e.message().find("the data URI holds 3 bytes"), std::string::npos) << e.what();
}

TEST(GltfBadInput, AFailedLoadTakesBackItsVariantsToo) {
  // The variant names are added before the images are read; an image that OpenImageIO cannot
  // read then fails the load, which must leave nothing of the file behind.
  nlohmann::json j = nlohmann::json::parse(squareGltf("{}", {1, 1, 1}));
  j["extensions"]["KHR_materials_variants"]["variants"] = {{{"name", "red"}}};
  j["images"] = {{{"uri", "data:image/png;base64," + base64("not an image")}}};
  SceneDescription scene;
  EXPECT_THROW(loadGltfFromMemory(j.dump(), "variants.gltf", &scene), SceneError);
  EXPECT_TRUE(scene.variants.empty());
  EXPECT_TRUE(scene.images.empty());
  j.erase("images");
  loadGltfFromMemory(j.dump(), "variants.gltf", &scene);
  EXPECT_EQ(scene.variants, std::vector<std::string>{"red"});
}

TEST(GltfBadInput, ImageDataThatDoesNotDecodeIsASceneErrorAtTheImage) {
  // A valid PNG header over damaged pixel data: loading reads the header only, building
  // decodes, and names the image.
  const std::string dir = test::scratchDir("GltfBadInput.ImageData");
  const std::string png = imageFileBytes(dir + "/n.png", 16, 16, {}, true);
  nlohmann::json j = nlohmann::json::parse(
      squareGltf(R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})", {1, 1, 1}));
  // Garbage inside the last IDAT chunk (lengths intact): the header reads, the pixels do not.
  std::string broken = png;
  for (size_t i = broken.size() - 32; i < broken.size() - 20; ++i) broken[i] = '\xff';
  j["images"] = {{{"uri", "data:image/png;base64," + base64(broken)}}};
  j["textures"] = {{{"source", 0}}};
  const std::string path = dir + "/cut.gltf";
  std::ofstream(path) << j.dump();
  SceneDescription s = load(path);
  SceneError e = test::errorFrom([&] { buildRenderScene(s); });
  EXPECT_EQ(e.where().pointer, "/images/0");
}

// ---------------------------------------------------------------------------------------------
// KHR_draco_mesh_compression
// ---------------------------------------------------------------------------------------------

// A unit cube [-1, 1]^3 of 12 triangles with flat normals, encoded by Draco (positions
// quantized to 16 bits, normals to 12), as a glTF whose accessors describe the decoded data
// (`pointsDelta` and `indicesDelta` make the POSITION and indices accessors lie about their
// counts).
std::string dracoCubeGltf(int pointsDelta = 0, int indicesDelta = 0) {
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(12);
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int nrm = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  int face = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.0f, 1.0f}) {
      // The face's corners, counter-clockwise seen from outside.
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Vec3f c[4];
      const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        c[k][axis] = side;
        c[k][u] = su[k];
        c[k][v] = side > 0 ? sv[k] : -sv[k];
      }
      Vec3f n;
      n[axis] = side;
      const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
      for (const auto& t : tris) {
        builder.SetAttributeValuesForFace(pos, draco::FaceIndex(face), &c[t[0]], &c[t[1]],
                                          &c[t[2]]);
        builder.SetAttributeValuesForFace(nrm, draco::FaceIndex(face), &n, &n, &n);
        ++face;
      }
    }
  std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 12);
  draco::EncoderBuffer buffer;
  if (!encoder.EncodeMeshToBuffer(*mesh, &buffer).ok()) throw std::runtime_error("draco encode");
  const std::string bytes(buffer.data(), buffer.size());
  // The decoded point count (Draco may merge or split corners).
  draco::DecoderBuffer in;
  in.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  const size_t points = std::move(decoder.DecodeMeshFromBuffer(&in)).value()->num_points();
  const uint32_t posId = mesh->attribute(pos)->unique_id(),
                 nrmId = mesh->attribute(nrm)->unique_id();
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_draco_mesh_compression"}},
      {"extensionsRequired", {"KHR_draco_mesh_compression"}},
      {"buffers",
       {{{"byteLength", bytes.size()},
         {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bytes.size()}}}},
      {"accessors",
       {{{"componentType", 5126},
         {"count", int(points) + pointsDelta},
         {"type", "VEC3"},
         {"min", {-1, -1, -1}},
         {"max", {1, 1, 1}}},
        {{"componentType", 5126}, {"count", int(points)}, {"type", "VEC3"}},
        {{"componentType", 5123}, {"count", 36 + indicesDelta}, {"type", "SCALAR"}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}},
            {"indices", 2},
            {"extensions",
             {{"KHR_draco_mesh_compression",
               {{"bufferView", 0},
                {"attributes", {{"POSITION", posId}, {"NORMAL", nrmId}}}}}}}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  return j.dump(1);
}

// A Draco cube loads as the cube: 12 triangles whose corners are the cube's (to the 16-bit
// quantization) and whose normals are the faces' axes, facing out.
TEST(GltfDraco, CompressedCubeDecodesToTheCube) {
  const std::string dir = test::scratchDir("GltfDraco.Cube");
  std::ofstream(dir + "/cube.gltf") << dracoCubeGltf();
  SceneDescription s = load(dir + "/cube.gltf");
  ASSERT_EQ(s.meshes.size(), 1u);
  const MeshDesc& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 36u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (size_t t = 0; t < 12; ++t) {
    const Vec3f p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]],
                p2 = m.positions[m.indices[3 * t + 2]];
    for (Vec3f p : {p0, p1, p2})
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(std::abs(p[c]), 1, 1e-3f);
    const Vec3f n = m.normals[m.indices[3 * t]];
    // Outward: the normal points the way the face's centre lies, and the winding agrees.
    const Vec3f centre = (p0 + p1 + p2) / 3;
    EXPECT_GT(dot(n, centre), 0.3f);
    EXPECT_GT(dot(cross(p1 - p0, p2 - p0), n), 0);
    EXPECT_NEAR(length(n), 1, 1e-3f);
  }
  expectBounds(s, {-1, -1, -1}, {1, 1, 1});
}

// Compressed data that disagrees with its accessors, or is not Draco at all, is exit 2 at the
// extension's pointer.
TEST(GltfBadInput, DracoBuffersThatLieAboutTheirSizesAreRejected) {
  const std::string dir = test::scratchDir("GltfDraco.Bad");
  const std::string ext = "/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression";
  std::ofstream(dir + "/points.gltf") << dracoCubeGltf(5, 0);
  expectError(dir + "/points.gltf", ext + "/attributes/POSITION", "points but accessor 0");
  std::ofstream(dir + "/indices.gltf") << dracoCubeGltf(0, -3);
  expectError(dir + "/indices.gltf", ext, "has 12 triangles (36 indices) but accessor 2");
  nlohmann::json j = nlohmann::json::parse(dracoCubeGltf());
  j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(std::string(64, 'x'));
  j["buffers"][0]["byteLength"] = 64;
  j["bufferViews"][0]["byteLength"] = 64;
  std::ofstream(dir + "/garbage.gltf") << j.dump();
  expectError(dir + "/garbage.gltf", ext + "/bufferView", "cannot decode the Draco mesh");
  // The committed seeds of the fuzzer's corpus (written by dracoCubeGltf) stay what they say.
  expectError(badFile("draco_point_count_mismatch.gltf"), ext + "/attributes/POSITION",
              "points but accessor 0");
  EXPECT_EQ(load(goodFile("draco_cube.gltf")).meshes.at(0).indices.size(), 36u);
}

// ---------------------------------------------------------------------------------------------
// EXT_meshopt_compression
// ---------------------------------------------------------------------------------------------

const Vec3f kCubeCorners[8] = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                               {-1, -1, 1},  {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
const uint32_t kCubeIndices[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};

// The cube's 8 corners and 36 indices compressed as gltfpack would: positions (float, stride
// 12), normals along the corners' diagonals (8-bit octahedral filter, stride 4) and triangle
// indices (16-bit), each a compressed view of a fallback buffer with no data.
// `shortPositions` cuts that many bytes off the compressed positions' byteLength.
std::string meshoptCubeGltf(size_t shortPositions = 0) {
  std::string compressed;
  std::vector<std::array<size_t, 2>> ranges;  // offset, length
  auto add = [&](const std::vector<unsigned char>& bytes, size_t length) {
    compressed.append(compressed.size() % 4 ? 4 - compressed.size() % 4 : 0, '\0');
    ranges.push_back({compressed.size(), length});
    compressed.append(reinterpret_cast<const char*>(bytes.data()), length);
  };
  std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(8, 12));
  add(out, meshopt_encodeVertexBuffer(out.data(), out.size(), kCubeCorners, 8, 12));
  float normals[8][4];
  for (int i = 0; i < 8; ++i) {
    const Vec3f n = normalize(kCubeCorners[i]);
    normals[i][0] = n.x, normals[i][1] = n.y, normals[i][2] = n.z, normals[i][3] = 0;
  }
  int8_t oct[8][4];
  meshopt_encodeFilterOct(oct, 8, 4, 8, &normals[0][0]);
  out.assign(meshopt_encodeVertexBufferBound(8, 4), 0);
  add(out, meshopt_encodeVertexBuffer(out.data(), out.size(), oct, 8, 4));
  out.assign(meshopt_encodeIndexBufferBound(36, 8), 0);
  add(out, meshopt_encodeIndexBuffer(out.data(), out.size(), kCubeIndices, 36));
  auto view = [&](size_t i, size_t offset, size_t length, int stride, size_t count,
                  const char* mode, const char* filter, size_t cut) {
    nlohmann::json ext = {{"buffer", 0},
                          {"byteOffset", ranges[i][0]},
                          {"byteLength", ranges[i][1] - cut},
                          {"byteStride", stride},
                          {"count", count},
                          {"mode", mode}};
    if (filter) ext["filter"] = filter;
    nlohmann::json v = {{"buffer", 1},
                        {"byteOffset", offset},
                        {"byteLength", length},
                        {"extensions", {{"EXT_meshopt_compression", ext}}}};
    if (std::string(mode) == "ATTRIBUTES") v["byteStride"] = stride;
    return v;
  };
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"EXT_meshopt_compression", "KHR_mesh_quantization"}},
      {"extensionsRequired", {"EXT_meshopt_compression", "KHR_mesh_quantization"}},
      {"buffers",
       {{{"byteLength", compressed.size()},
         {"uri", "data:application/octet-stream;base64," + base64(compressed)}},
        {{"byteLength", 96 + 32 + 72},
         {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}}},
      {"bufferViews",
       {view(0, 0, 96, 12, 8, "ATTRIBUTES", nullptr, shortPositions),
        view(1, 96, 32, 4, 8, "ATTRIBUTES", "OCTAHEDRAL", 0),
        view(2, 128, 72, 2, 36, "TRIANGLES", nullptr, 0)}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 8},
         {"type", "VEC3"},
         {"min", {-1, -1, -1}},
         {"max", {1, 1, 1}}},
        {{"bufferView", 1},
         {"componentType", 5120},
         {"normalized", true},
         {"count", 8},
         {"type", "VEC3"}},
        {{"bufferView", 2}, {"componentType", 5123}, {"count", 36}, {"type", "SCALAR"}}}},
      {"meshes",
       {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  return j.dump(1);
}

// gltfpack-style compression decodes to the cube: the corners exactly (positions are
// lossless), the normals to the 8-bit octahedral encoding's precision, the triangles exactly.
TEST(GltfMeshopt, CompressedCubeDecodesToTheCube) {
  const std::string dir = test::scratchDir("GltfMeshopt.Cube");
  std::ofstream(dir + "/cube.gltf") << meshoptCubeGltf();
  for (const std::string& file : {dir + "/cube.gltf", goodFile("meshopt_cube.gltf")}) {
    SCOPED_TRACE(file);
    SceneDescription s = load(file);
    ASSERT_EQ(s.meshes.size(), 1u);
    const MeshDesc& m = s.meshes[0];
    ASSERT_EQ(m.positions.size(), 8u);
    ASSERT_EQ(m.indices.size(), 36u);
    for (size_t i = 0; i < 8; ++i) {
      EXPECT_EQ(m.positions[i], kCubeCorners[i]);
      expectNear(m.normals[i], normalize(kCubeCorners[i]), 0.03f);
    }
    // The index codec may rotate a triangle's corners, never its winding.
    for (size_t t = 0; t < 12; ++t) {
      const uint32_t* a = &kCubeIndices[3 * t];
      const uint32_t* b = &m.indices[3 * t];
      bool rotation = false;
      for (int r = 0; r < 3; ++r)
        rotation = rotation || (b[0] == a[r] && b[1] == a[(r + 1) % 3] && b[2] == a[(r + 2) % 3]);
      EXPECT_TRUE(rotation) << "triangle " << t;
    }
  }
}

// Compressed bytes that do not decode to what the view says, and strides the extension does
// not allow, are exit 2 at the extension.
TEST(GltfBadInput, MeshoptViewsThatLieAboutTheirSizesAreRejected) {
  const std::string dir = test::scratchDir("GltfMeshopt.Bad");
  const std::string ext = "/bufferViews/0/extensions/EXT_meshopt_compression";
  std::ofstream(dir + "/short.gltf") << meshoptCubeGltf(5);
  expectError(dir + "/short.gltf", ext, "cannot decode the compressed ATTRIBUTES");
  expectError(badFile("meshopt_truncated.gltf"), ext, "cannot decode the compressed ATTRIBUTES");
  nlohmann::json j = nlohmann::json::parse(meshoptCubeGltf());
  j["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 3;
  std::ofstream(dir + "/stride.gltf") << j.dump();
  expectError(dir + "/stride.gltf", "/bufferViews/2/extensions/EXT_meshopt_compression/byteStride",
              "must be 2 or 4 for TRIANGLES");
  j = nlohmann::json::parse(meshoptCubeGltf());
  j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 9;
  std::ofstream(dir + "/count.gltf") << j.dump();
  expectError(dir + "/count.gltf", ext + "/count", "do not fit the view's byteLength 96");
}

}  // namespace
}  // namespace glint
