// glint — the sidecar's area and projective lights and its "environment".
#include "scenes/sidecar_lights.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "scenes/paths.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

float radians(float degrees) { return degrees * (kPi / 180.0f); }

// A frame at `eye` whose -Z points along `dir` (read from `dirKey`), +Y towards `up`.
Transform aimed(const JsonReader& r, Vec3f eye, Vec3f dir, const char* dirKey,
                std::optional<Vec3f> up) {
  if (dir == Vec3f{}) throw SceneError(r.where(dirKey), "must not be zero");
  const Vec3f d = normalize(dir);
  Vec3f u = up ? *up : (std::abs(d.y) > 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0});
  // A user-facing sanity check on unit vectors: sin(angle) below 1e-6 means "parallel".
  if (u == Vec3f{} || length(cross(d, normalize(u))) < 1e-6f)
    throw SceneError(r.where("up"), "must be non-zero and not parallel to the direction");
  return Transform::lookAt(eye, eye + d, u);
}

// "look_at" or "direction" (exactly one), from `position`.
Vec3f aimFrom(JsonReader& r, Vec3f position, const char** key) {
  if (r.has("look_at") == r.has("direction"))
    throw SceneError(r.where(), "needs exactly one of 'look_at' or 'direction'");
  *key = r.has("look_at") ? "look_at" : "direction";
  return r.has("look_at") ? r.get<Vec3f>("look_at") - position : r.get<Vec3f>("direction");
}

int textureNamed(const SceneDescription& scene, const std::string& name, const SourceLocation& at) {
  for (size_t i = 0; i < scene.textures.size(); ++i)
    if (scene.textures[i].name == name) return int(i);
  throw SceneError(at, "no texture named '" + name + "'");
}

}  // namespace

bool usesTransform(const JsonReader& r, std::initializer_list<const char*> others) {
  if (!r.has("transform")) return false;
  for (const char* key : others)
    if (r.has(key))
      throw SceneError(r.where(key),
                       "give either a 'transform' or '" + std::string(key) + "', not both");
  return true;
}

bool isSidecarOnlyLight(LightType type) {
  return type == LightType::Quad || type == LightType::Disk || type == LightType::Sphere ||
         type == LightType::Projective;
}

void readSidecarLight(JsonReader& r, const SceneDescription& scene, LightDesc* light) {
  if (light->type != LightType::Projective)
    light->twoSided = r.get<bool>("two_sided", light->twoSided);
  switch (light->type) {
    case LightType::Quad: {
      light->corner = r.get<Vec3f>("corner");
      light->edgeU = r.get<Vec3f>("edge_u");
      light->edgeV = r.get<Vec3f>("edge_v");
      // Relative to the edges' lengths: parallel or zero edges span no area.
      const float scale = length(light->edgeU) * length(light->edgeV);
      if (!(length(cross(light->edgeU, light->edgeV)) > 1e-6f * scale))
        throw SceneError(r.where("edge_v"),
                         "must not be zero or parallel to edge_u (the quad "
                         "would have no area)");
      // The corner and edges are in the transform's space when there is one.
      light->worldFromLight = r.get<Transform>("transform", Transform());
      break;
    }
    case LightType::Disk: {
      light->radius = r.get<float>("radius", kPositive);
      if (usesTransform(r, {"position", "direction"})) {  // in the frame's XY plane, facing -Z
        light->worldFromLight = r.get<Transform>("transform");
        break;
      }
      const Vec3f position = r.get<Vec3f>("position");
      const Vec3f dir = r.get<Vec3f>("direction");
      light->worldFromLight = aimed(r, position, dir, "direction", std::nullopt);
      break;
    }
    case LightType::Sphere:
      light->radius = r.get<float>("radius", kPositive);
      light->worldFromLight = usesTransform(r, {"position"})
                                  ? r.get<Transform>("transform")
                                  : Transform::translate(r.get<Vec3f>("position"));
      break;
    case LightType::Projective: {
      light->fov = radians(r.get<float>("fov_degrees", 45, {.gt = 0, .lt = 180}));
      light->attenuation = r.get<float>("attenuation", light->attenuation, kUnit);
      if (r.has("texture"))
        light->texture = textureNamed(scene, r.get<std::string>("texture"), r.where("texture"));
      const Vec3f position = r.get<Vec3f>("position");
      const char* key = "direction";
      const Vec3f dir = aimFrom(r, position, &key);
      light->worldFromLight = aimed(r, position, dir, key, r.optional<Vec3f>("up"));
      break;
    }
    default:
      break;
  }
}

void readEnvironment(JsonReader& root, const std::string& file, SceneDescription* scene) {
  JsonReader* r = root.optionalObject("environment");
  if (!r) return;
  EnvironmentDesc env;
  env.where = r->where();
  std::vector<std::string> given;
  for (const char* key : {"color", "image", "preset"})
    if (r->has(key)) given.push_back(key);
  if (given.size() > 1)
    throw SceneError(r->where(given[1]), "give one of 'color', 'image' and 'preset', not " +
                                             std::string(given.size() == 2 ? "both" : "all three"));
  env.color = r->get<Rgb>("color", env.color, kNonNegative);
  env.intensity = r->get<float>("intensity", env.intensity, kNonNegative);
  env.rotation = radians(r->get<float>("rotation_degrees", 0));
  if (r->has("preset")) {
    const std::string preset = r->get<std::string>("preset");
    if (preset != "studio")
      throw SceneError(r->where("preset"), "unknown preset '" + preset + "' (studio)");
    env.studio = true;
  }
  if (r->has("image")) {
    const std::string relative = r->get<std::string>("image");
    const fs::path path = existingScenePath(relative, file, r->where("image"));
    if (!isEnvironmentImagePath(path.string()))
      throw SceneError(r->where("image"),
                       "expected a scene-linear image, OpenEXR (.exr) or Radiance (.hdr), got '" +
                           relative + "'");
    env.image = path.string();
  }
  scene->environment = env;
}

bool isEnvironmentImagePath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".exr" || ext == ".hdr";
}

}  // namespace glint
