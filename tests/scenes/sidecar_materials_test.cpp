// glint tests — the sidecar's "textures" and "materials" sections: what they read, how they
// reach the built scene, and the errors for bad input (file, JSON pointer, message).
#include "scenes/sidecar_materials.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "materials/material.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

constexpr const char* kFile = "mat.glint.json";

SceneDescription apply(const std::string& text, SceneDescription scene = {}) {
  applySceneJsonText(text, kFile, SceneJsonKind::Sidecar, &scene);
  return scene;
}

SceneError applyError(const std::string& text, SceneDescription scene = {}) {
  return errorFrom([&] { applySceneJsonText(text, kFile, SceneJsonKind::Sidecar, &scene); });
}

// A description with one glTF-like material "Paint" and a mesh node "Statue" using it.
SceneDescription gltfLike() {
  SceneDescription d;
  MaterialDesc paint;
  paint.name = "Paint";
  paint.baseColorTexture = -1;
  d.materials.push_back(paint);
  MeshDesc mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.material = 0;
  d.meshes.push_back(mesh);
  InstanceDesc inst;
  inst.mesh = 0;
  inst.node = "Statue";
  d.instances.push_back(inst);
  return d;
}

TEST(SidecarMaterials, ReadsEveryMaterialType) {
  SceneDescription d = apply(R"({"materials": [
    {"name": "a", "type": "glass", "ior": 1.33, "color": [0.9, 1, 0.9]},
    {"name": "b", "type": "mirror", "color": [0.8, 0.8, 0.8]},
    {"name": "c", "type": "blinn_phong", "diffuse": [0.5, 0.5, 0.5], "specular": [0.2, 0.2, 0.2], "shininess": 30},
    {"name": "d", "type": "pbr", "base_color": [1, 0.8, 0.3], "metallic": 1, "roughness": 0.25, "ior": 1.45, "transmission": 0.5},
    {"name": "e", "type": "eyelight", "color": [1, 0, 0], "transparency": 0.25},
    {"name": "f", "type": "random", "mode": "primitive", "seed": 7, "shading": "lambert"},
    {"name": "g", "type": "glass", "roughness": 0.2}
  ]})");
  ASSERT_EQ(d.materials.size(), 7u);
  EXPECT_EQ(d.materials[0].type, MaterialType::Glass);
  EXPECT_FLOAT_EQ(d.materials[0].ior, 1.33f);
  EXPECT_EQ(d.materials[0].roughness, 0.0f);  // glass is smooth unless told
  EXPECT_EQ(d.materials[1].type, MaterialType::Mirror);
  EXPECT_EQ(d.materials[2].type, MaterialType::BlinnPhong);
  EXPECT_FLOAT_EQ(d.materials[3].roughness, 0.25f);
  EXPECT_FLOAT_EQ(d.materials[3].transmission, 0.5f);
  EXPECT_FLOAT_EQ(d.materials[4].opacity, 0.75f);
  EXPECT_EQ(d.materials[4].alphaMode, AlphaModeDesc::Blend);
  EXPECT_EQ(d.materials[5].randomMode, TextureDesc::RandomMode::Primitive);
  EXPECT_TRUE(d.materials[5].randomLit);
  EXPECT_FLOAT_EQ(d.materials[6].roughness, 0.2f);
  const std::vector<std::string> names = {"glass",    "mirror", "blinn_phong", "pbr",
                                          "eyelight", "random", "glass"};
  for (size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(materialTypeName(d.materials[i].type), names[i]);
}

TEST(SidecarMaterials, TexturesAreDefinedOnceAndReferencedByName) {
  SceneDescription d = apply(R"({
    "textures": [
      {"name": "veins", "type": "marble", "seed": 3, "frequency": 5, "colors": [[1, 1, 1], [0.1, 0.1, 0.3]],
       "mapping": {"space": "world", "scale": 2, "offset": [1, 2, 3]}},
      {"name": "height", "type": "fbm", "octaves": 4},
      {"name": "tiles", "type": "checker", "colors": [[0, 0, 0], [1, 1, 1]], "mapping": {"plane": "xz", "space": "world"}}
    ],
    "materials": [
      {"name": "stone", "type": "lambert", "diffuse": "veins", "bump": {"texture": "height", "strength": 0.1}},
      {"name": "floor", "type": "phong", "diffuse": "tiles", "specular": [0.1, 0.1, 0.1], "shininess": 20}
    ]})");
  ASSERT_EQ(d.textures.size(), 3u);
  EXPECT_EQ(d.textures[0].kind, TextureKind::Noise);
  EXPECT_EQ(d.textures[0].noise, NoiseKind::Marble);
  EXPECT_EQ(d.textures[0].mapping.space, MappingDesc::Space::World);
  EXPECT_EQ(d.textures[0].mapping.scale, (Vec3f{2, 2, 2}));
  EXPECT_EQ(d.textures[0].mapping.offset, (Vec3f{1, 2, 3}));
  EXPECT_EQ(d.textures[1].mapping.space, MappingDesc::Space::Object);  // noise default
  EXPECT_EQ(d.textures[2].mapping.plane, MappingDesc::Plane::Xz);
  EXPECT_EQ(d.materials[0].baseColorTexture, 0);
  EXPECT_EQ(d.materials[0].baseColor, (Rgb{1, 1, 1}));
  EXPECT_EQ(d.materials[0].bumpTexture, 1);
  EXPECT_FLOAT_EQ(d.materials[0].bumpStrength, 0.1f);
  EXPECT_EQ(d.materials[1].baseColorTexture, 2);
}

TEST(SidecarMaterials, NodesTakeAssignedMaterials) {
  SceneDescription d = apply(
      R"({"materials": [{"name": "marble", "type": "lambert", "nodes": ["Statue"]}]})", gltfLike());
  EXPECT_EQ(d.instances[0].material, 1);
  // The override builds one more material than the glTF's own.
  RenderScene scene = buildRenderScene(d);
  EXPECT_EQ(scene.geometry().meshes.size(), 1u);
}

TEST(SidecarMaterials, OverrideSwitchesAGltfMaterialToGlass) {
  SceneDescription d =
      apply(R"({"materials": [{"name": "Paint", "type": "glass", "ior": 1.7}]})", gltfLike());
  EXPECT_EQ(d.materials[0].type, MaterialType::Glass);
  EXPECT_EQ(d.materials[0].roughness, 0.0f);
  RenderScene scene = buildRenderScene(d);
  EXPECT_TRUE(scene.features().has(Feature::Refraction));
  EXPECT_FALSE(scene.features().has(Feature::Textures));
}

// A glTF material overridden into an impossible Phong is reported at the override (the
// sidecar's file and pointer), where the user can fix it.
TEST(SidecarMaterials, ErrorsInAnOverrideNameTheOverride) {
  SceneDescription gltf = gltfLike();
  gltf.materials[0].where = {"statue.glb", "/materials/0"};
  const SceneDescription d = apply(R"({"materials": [{"name": "Paint", "type": "phong",
    "diffuse": [0.9, 0.9, 0.9], "specular": [0.3, 0.3, 0.3]}]})",
                                   gltf);
  EXPECT_SCENE_ERROR(errorFrom([&] { buildRenderScene(d); }), kFile, "/materials/0", "exceeds 1");
}

TEST(SidecarMaterials, FeaturesFollowTheMaterials) {
  SceneDescription d = apply(R"({
    "textures": [{"name": "h", "type": "noise"}],
    "materials": [{"name": "Paint", "type": "lambert", "bump": {"texture": "h"}}]})",
                             gltfLike());
  RenderScene scene = buildRenderScene(d);
  EXPECT_TRUE(scene.features().has(Feature::Bump));
  EXPECT_TRUE(scene.features().has(Feature::Procedural));
  EXPECT_FALSE(scene.features().has(Feature::Textures));
  EXPECT_FALSE(scene.features().has(Feature::Refraction));
  EXPECT_FALSE(scene.features().has(Feature::Transparency));
  // A plain scene calls for none of them, so it pays for none of them.
  RenderScene plain = buildRenderScene(gltfLike());
  for (Feature f : {Feature::Bump, Feature::Procedural, Feature::Textures, Feature::Refraction,
                    Feature::Transparency})
    EXPECT_FALSE(plain.features().has(f)) << featureName(f);
  EXPECT_FALSE(plain.materials()[0]->traits().needs.uvs);
  EXPECT_FALSE(plain.materials()[0]->traits().needs.tangents);
}

// ---------------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------------

TEST(SidecarMaterials, UnknownMaterialTypeIsAnError) {
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "x", "type": "glas"}]})"), kFile,
                     "/materials/0/type", "glass");
}

TEST(SidecarMaterials, IorMustBePositive) {
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "x", "type": "glass", "ior": -1.5}]})"),
                     kFile, "/materials/0/ior", "must be > 0");
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "x", "type": "pbr", "ior": 0}]})"),
                     kFile, "/materials/0/ior", "must be > 0");
}

TEST(SidecarMaterials, RoughnessMustBeInTheUnitInterval) {
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "x", "type": "pbr", "roughness": 1.5}]})"), kFile,
      "/materials/0/roughness", "must be >= 0 and <= 1");
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "x", "type": "glass", "roughness": -0.1}]})"), kFile,
      "/materials/0/roughness", "must be >= 0 and <= 1");
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "x", "type": "pbr", "transmission": 2}]})"), kFile,
      "/materials/0/transmission", "must be >= 0 and <= 1");
}

// The pbr type takes glTF's material extensions as objects; an override of a glTF material
// changes only the layers and factors it names.
TEST(SidecarMaterials, PbrTakesTheExtensionLayers) {
  const SceneDescription d = apply(R"({"materials": [{"name": "coated", "type": "pbr",
      "specular": {"strength": 0.5, "color": [1, 0.5, 0.25]},
      "clearcoat": {"roughness": 0.2}, "sheen": {"color": [0.1, 0.2, 0.3], "roughness": 0.7},
      "volume": {"thickness": 2, "attenuation_color": [0.9, 0.8, 0.7],
                 "attenuation_distance": 3},
      "iridescence": {"factor": 0.6, "ior": 1.4, "thickness_nm": 350},
      "anisotropy": {"strength": 0.8, "rotation": 1.5}, "dispersion": 0.25,
      "diffuse_transmission": {"factor": 0.3, "color": [0.5, 1, 0.5]}}]})");
  ASSERT_EQ(d.materials.size(), 1u);
  const MaterialLayersDesc& l = d.materials[0].layers;
  EXPECT_FLOAT_EQ(l.specular, 0.5f);
  EXPECT_FLOAT_EQ(l.specularColor.z, 0.25f);
  EXPECT_FLOAT_EQ(l.clearcoat, 1);  // an object without a factor switches the layer on
  EXPECT_FLOAT_EQ(l.clearcoatRoughness, 0.2f);
  EXPECT_FLOAT_EQ(l.sheenColor.y, 0.2f);
  EXPECT_FLOAT_EQ(l.sheenRoughness, 0.7f);
  EXPECT_FLOAT_EQ(l.thickness, 2);
  EXPECT_FLOAT_EQ(l.attenuationColor.x, 0.9f);
  EXPECT_FLOAT_EQ(l.attenuationDistance, 3);
  EXPECT_FLOAT_EQ(l.iridescence, 0.6f);
  EXPECT_FLOAT_EQ(l.iridescenceIor, 1.4f);
  EXPECT_FLOAT_EQ(l.iridescenceThicknessMin, 350);
  EXPECT_FLOAT_EQ(l.iridescenceThicknessMax, 350);
  EXPECT_FLOAT_EQ(l.anisotropy, 0.8f);
  EXPECT_FLOAT_EQ(l.anisotropyRotation, 1.5f);
  EXPECT_FLOAT_EQ(l.dispersion, 0.25f);
  EXPECT_FLOAT_EQ(l.diffuseTransmission, 0.3f);
  EXPECT_FLOAT_EQ(l.diffuseTransmissionColor.x, 0.5f);
  // An override keeps what it does not name.
  SceneDescription g = gltfLike();
  g.materials[0].layers.sheenColor = {1, 1, 1};
  g.materials[0].layers.sheenColorTexture = 4;
  g = apply(R"({"materials": [{"name": "Paint", "clearcoat": {"factor": 0.5}}]})", g);
  EXPECT_FLOAT_EQ(g.materials[0].layers.clearcoat, 0.5f);
  EXPECT_EQ(g.materials[0].layers.sheenColorTexture, 4);
  // Bad values and unknown keys name their pointer.
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "x", "type": "pbr", "clearcoat": {"factor": 2}}]})"),
      kFile, "/materials/0/clearcoat/factor", "must be >= 0 and <= 1");
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"materials": [{"name": "x", "type": "pbr", "volume": {"attenuation_distance": 0}}]})"),
      kFile, "/materials/0/volume/attenuation_distance", "must be > 0");
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"materials": [{"name": "x", "type": "pbr", "sheen": {"colour": [1, 1, 1]}}]})"),
      kFile, "/materials/0/sheen/colour", "color");
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "x", "type": "pbr", "dispersion": -1}]})"), kFile,
      "/materials/0/dispersion", "must be >= 0");
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "x", "type": "lambert", "sheen": {}}]})"), kFile,
      "/materials/0/sheen", "");
}

TEST(SidecarMaterials, MissingTextureFileNamesThePath) {
  SceneError e = applyError(
      R"({"textures": [{"name": "bricks", "type": "image", "file": "no/such/bricks.png"}]})");
  EXPECT_SCENE_ERROR(e, kFile, "/textures/0/file", "file not found");
  EXPECT_NE(e.message().find("no/such/bricks.png"), std::string::npos) << e.what();
}

TEST(SidecarMaterials, UnknownTextureNameSuggestsTheClosest) {
  EXPECT_SCENE_ERROR(applyError(R"({"textures": [{"name": "marble", "type": "marble"}],
      "materials": [{"name": "x", "type": "lambert", "diffuse": "marbel"}]})"),
                     kFile, "/materials/0/diffuse", "did you mean 'marble'");
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "x", "type": "lambert",
      "bump": {"texture": "h"}}]})"),
                     kFile, "/materials/0/bump/texture", "no texture named 'h'");
}

TEST(SidecarMaterials, TextureParametersAreValidated) {
  EXPECT_SCENE_ERROR(applyError(R"({"textures": [{"name": "t", "type": "marbel"}]})"), kFile,
                     "/textures/0/type", "marble");
  EXPECT_SCENE_ERROR(applyError(R"({"textures": [{"name": "t", "type": "fbm", "octaves": 0}]})"),
                     kFile, "/textures/0/octaves", "must be >= 1");
  EXPECT_SCENE_ERROR(
      applyError(R"({"textures": [{"name": "t", "type": "noise", "mapping": {"scale": -1}}]})"),
      kFile, "/textures/0/mapping/scale", "must be > 0");
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"textures": [{"name": "t", "type": "noise", "mapping": {"space": "screen"}}]})"),
      kFile, "/textures/0/mapping/space", "uv");
  EXPECT_SCENE_ERROR(
      applyError(R"({"textures": [{"name": "t", "type": "checker", "colors": [[1, 1, 1]]}]})"),
      kFile, "/textures/0/colors", "two colours");
  EXPECT_SCENE_ERROR(applyError(R"({"textures": [{"name": "t", "type": "wood", "frequency": 3}]})"),
                     kFile, "/textures/0/frequency", "unknown key");
  EXPECT_SCENE_ERROR(applyError(R"({"textures": [{"name": "t", "type": "noise"},
                                                 {"name": "t", "type": "wood"}]})"),
                     kFile, "/textures/1/name", "duplicate texture name");
}

TEST(SidecarMaterials, OneNormalModifierPerMaterial) {
  EXPECT_SCENE_ERROR(applyError(R"({"textures": [{"name": "h", "type": "noise"}],
      "materials": [{"name": "x", "type": "lambert", "bump": {"texture": "h"}, "snow": {}}]})"),
                     kFile, "/materials/0", "at most one");
}

TEST(SidecarMaterials, UnknownNodeSuggestsTheClosest) {
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "m", "type": "lambert",
      "nodes": ["Statu"]}]})",
                                gltfLike()),
                     kFile, "/materials/0/nodes/0", "did you mean 'Statue'");
}

TEST(SidecarMaterials, UnreadableImageIsAnErrorAtTheTexture) {
  std::string dir = test::scratchDir("sidecar_bad_image");
  { std::ofstream(dir + "/broken.png") << "not a png at all"; }
  std::string sidecar = dir + "/scene.glint.json";
  {
    std::ofstream(sidecar)
        << R"({"textures": [{"name": "b", "type": "image", "file": "broken.png"}],
      "materials": [{"name": "Paint", "type": "lambert", "diffuse": "b"}]})";
  }
  SceneDescription d = gltfLike();
  applySceneJsonFile(sidecar, SceneJsonKind::Sidecar, &d);
  SceneError e = errorFrom([&] { buildRenderScene(d); });
  EXPECT_EQ(e.where().file, sidecar);
  EXPECT_EQ(e.where().pointer, "/textures/0");
  EXPECT_NE(e.message().find("broken.png"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace glint
