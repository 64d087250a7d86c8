// glint — the glint JSON schema (sidecars and .json scenes), read into a SceneDescription.
#include "scenes/sidecar.h"

#include <filesystem>

#include "geometry/accel/accelerator.h"
#include "scenes/gltf_loader.h"
#include "scenes/json_reader.h"
#include "scenes/json_util.h"
#include "scenes/sidecar_materials.h"
#include "scenes/sidecar_objects.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

// Names accepted by the render block (accelerators come from their factory). Add an
// integrator here when it lands ("path", ...).
const std::vector<std::string> kIntegrators = {"whitted"};
const std::vector<std::string> kFilters = {"box", "tent", "gaussian"};
const std::vector<std::string> kToneMapOperators = {"none", "ward"};

float radians(float degrees) { return degrees * (kPi / 180.0f); }

// ---------------------------------------------------------------------------------------------
// render
// ---------------------------------------------------------------------------------------------

// Fills `s` from the render block; a missing key keeps the value already there.
void readRender(JsonReader& r, RenderSettings* s) {
  if (auto width = r.optional<int>("width", kPositive)) s->width = width;
  if (auto height = r.optional<int>("height", kPositive)) s->height = height;
  s->spp = r.get<int>("spp", s->spp, kPositive);
  s->seed = r.get<uint64_t>("seed", s->seed);
  s->threads = r.get<int>("threads", s->threads, kNonNegative);
  s->accel = r.oneOf("accel", acceleratorNames(), s->accel);
  s->camera = r.get<std::string>("camera", s->camera);
  s->integrator = r.oneOf("integrator", kIntegrators, s->integrator);
  s->maxDepth = r.get<int>("max_depth", s->maxDepth, kNonNegative);
  if (JsonReader* f = r.optionalObject("filter")) {
    s->filter.type = f->oneOf("type", kFilters, s->filter.type);
    s->filter.radius = f->get<float>("radius", s->filter.radius, kPositive);
  }
  s->background = r.get<Rgb>("background", s->background, kNonNegative);
  if (JsonReader* e = r.optionalObject("exr")) {
    s->exrHalf = e->get<bool>("half", s->exrHalf);
    s->aovs = e->get<bool>("aovs", s->aovs);
  }
  if (JsonReader* t = r.optionalObject("tonemap")) {
    ToneMapSettings& tm = s->tonemap;
    tm.exposure = t->get<float>("exposure", tm.exposure);
    tm.op = t->oneOf("operator", kToneMapOperators, tm.op);
    if (JsonReader* w = t->optionalObject("ward")) {
      tm.wardDisplayMax = w->get<float>("display_max", tm.wardDisplayMax, kPositive);
      tm.wardSceneLuminance = w->get<float>("scene_luminance", tm.wardSceneLuminance, kPositive);
    }
    tm.display = t->get<std::string>("display", tm.display);
    tm.view = t->get<std::string>("view", tm.view);
  }
}

// render.camera must name a camera once every file has been applied.
void checkRenderCamera(JsonReader& render, const SceneDescription& scene) {
  if (!render.has("camera")) return;
  const std::string& name = scene.render.camera;
  std::string available;
  for (const CameraDesc& c : scene.cameras) {
    if (c.name == name) return;
    available += (available.empty() ? "'" : ", '") + c.name + "'";
  }
  throw SceneError(render.where("camera"), "no camera named '" + name + "'; " +
                                               (available.empty() ? "the scene has no cameras"
                                                                  : "available: " + available));
}

// ---------------------------------------------------------------------------------------------
// Placement: position + look_at (or direction), or a transform
// ---------------------------------------------------------------------------------------------

// A frame at `eye` whose -Z points along `dir`, +Y towards `up`.
Transform aimAlong(const JsonReader& r, Vec3f eye, Vec3f dir, Vec3f up, const char* dirKey,
                   const char* upKey) {
  if (dir == Vec3f{})
    throw SceneError(r.where(dirKey), std::string(dirKey) == "look_at" ? "must differ from position"
                                                                       : "must not be zero");
  if (up == Vec3f{}) throw SceneError(r.where(upKey), "must not be zero");
  // A user-facing sanity check on unit vectors: sin(angle) below 1e-6 means "parallel".
  if (length(cross(normalize(dir), normalize(up))) < 1e-6f)
    throw SceneError(r.where(upKey), "must not be parallel to the view direction");
  return Transform::lookAt(eye, eye + dir, up);
}

// Any up vector that is not parallel to `dir` (lights are symmetric about their axis).
Vec3f someUp(Vec3f dir) {
  Vec3f d = normalize(dir);
  return std::abs(d.y) > 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
}

// Rejects `others` when "transform" is given, so a frame is never specified twice.
bool usesTransform(const JsonReader& r, std::initializer_list<const char*> others) {
  if (!r.has("transform")) return false;
  for (const char* key : others)
    if (r.has(key))
      throw SceneError(r.where(key),
                       "give either a 'transform' or '" + std::string(key) + "', not both");
  return true;
}

// ---------------------------------------------------------------------------------------------
// cameras
// ---------------------------------------------------------------------------------------------

CameraDesc readCamera(JsonReader& r) {
  CameraDesc cam;
  cam.where = r.where();
  cam.name = r.get<std::string>("name", "");
  cam.type = r.oneOf<CameraType>(
      "type",
      {{"perspective", CameraType::Perspective}, {"orthographic", CameraType::Orthographic}},
      CameraType::Perspective);
  if (cam.type == CameraType::Perspective) {
    cam.yfov = radians(r.get<float>("yfov_degrees", 40, {.gt = 0, .lt = 180}));
    cam.aspectRatio = r.get<float>("aspect_ratio", 0, kPositive);
  } else {
    cam.xmag = r.get<float>("xmag", cam.xmag, kPositive);
    cam.ymag = r.get<float>("ymag", cam.ymag, kPositive);
  }
  cam.znear = r.get<float>("znear", cam.znear, kNonNegative);
  cam.zfar = r.get<float>("zfar", cam.zfar, kPositive);
  if (cam.znear >= cam.zfar)
    throw SceneError(r.where("znear"), "must be < zfar (znear " + std::to_string(cam.znear) +
                                           ", zfar " + std::to_string(cam.zfar) + ")");
  if (usesTransform(r, {"position", "look_at", "up"})) {
    cam.worldFromCamera = r.get<Transform>("transform");
  } else {
    if (!r.has("position") || !r.has("look_at"))
      throw SceneError(r.where(), "a camera needs 'position' and 'look_at', or a 'transform'");
    Vec3f eye = r.get<Vec3f>("position");
    Vec3f target = r.get<Vec3f>("look_at");
    Vec3f up = r.get<Vec3f>("up", Vec3f{0, 1, 0});
    cam.worldFromCamera = aimAlong(r, eye, target - eye, up, "look_at", "up");
  }
  return cam;
}

// A camera named like an existing one replaces it; others are added.
void readCameras(JsonReader& root, SceneDescription* scene) {
  std::vector<std::pair<std::string, std::string>> seen;  // name, pointer
  for (JsonReader* r : root.objects("cameras")) {
    CameraDesc cam = readCamera(*r);
    bool replaced = false;
    if (!cam.name.empty()) {
      for (const auto& [name, pointer] : seen)
        if (name == cam.name)
          throw SceneError(r->where("name"),
                           "duplicate camera name '" + cam.name + "' (also at " + pointer + ")");
      seen.emplace_back(cam.name, r->where().pointer);
      for (CameraDesc& existing : scene->cameras)
        if (existing.name == cam.name) existing = cam, replaced = true;
    }
    if (!replaced) scene->cameras.push_back(cam);
  }
}

// ---------------------------------------------------------------------------------------------
// lights
// ---------------------------------------------------------------------------------------------

LightDesc readLight(JsonReader& r) {
  LightDesc light;
  light.where = r.where();
  light.name = r.get<std::string>("name", "");
  light.type = r.oneOf<LightType>("type", {{"point", LightType::Point},
                                           {"spot", LightType::Spot},
                                           {"directional", LightType::Directional}});
  light.color = r.get<Rgb>("color", light.color, kNonNegative);
  light.intensity = r.get<float>("intensity", light.intensity, kNonNegative);
  light.castsShadows = r.get<bool>("cast_shadows", light.castsShadows);
  if (light.type != LightType::Directional)
    light.range = r.get<float>("range", light.range, kNonNegative);

  switch (light.type) {
    case LightType::Point:
      if (usesTransform(r, {"position"}))
        light.worldFromLight = r.get<Transform>("transform");
      else
        light.worldFromLight = Transform::translate(r.get<Vec3f>("position"));
      break;
    case LightType::Spot: {
      float outer = r.get<float>("outer_cone_degrees", 45, {.ge = 0, .le = 90});
      float inner = r.get<float>("inner_cone_degrees", 0, {.ge = 0, .le = 90});
      if (inner > outer)
        throw SceneError(r.where("inner_cone_degrees"),
                         "must be <= outer_cone_degrees (" + std::to_string(outer) + ")");
      light.innerConeAngle = radians(inner);
      light.outerConeAngle = radians(outer);
      if (usesTransform(r, {"position", "look_at", "direction"})) {
        light.worldFromLight = r.get<Transform>("transform");
        break;
      }
      Vec3f pos = r.get<Vec3f>("position");
      if (r.has("look_at") == r.has("direction"))
        throw SceneError(r.where(), "a spot light needs exactly one of 'look_at' or 'direction'");
      bool target = r.has("look_at");
      Vec3f dir = target ? r.get<Vec3f>("look_at") - pos : r.get<Vec3f>("direction");
      const char* key = target ? "look_at" : "direction";
      light.worldFromLight = aimAlong(r, pos, dir, dir == Vec3f{} ? dir : someUp(dir), key, key);
      break;
    }
    case LightType::Directional:
      if (usesTransform(r, {"direction"})) {
        light.worldFromLight = r.get<Transform>("transform");
      } else {
        Vec3f dir = r.get<Vec3f>("direction");
        light.worldFromLight =
            aimAlong(r, {}, dir, dir == Vec3f{} ? dir : someUp(dir), "direction", "direction");
      }
      break;
  }
  return light;
}

void readLights(JsonReader& root, SceneDescription* scene) {
  for (JsonReader* r : root.objects("lights")) scene->lights.push_back(readLight(*r));
}

// ---------------------------------------------------------------------------------------------
// gltf (only in a .json scene)
// ---------------------------------------------------------------------------------------------

void loadGltfList(JsonReader& root, const std::string& file, SceneDescription* scene) {
  fs::path folder = fs::path(file).parent_path();
  for (const JsonItem& entry : root.optionalArray("gltf")) {
    std::string relative;
    SourceLocation at = entry.where;
    Transform transform;
    if (entry.value->is_object()) {
      JsonReader& r = root.item(entry);
      relative = r.get<std::string>("file");
      at = r.where("file");
      transform = r.get<Transform>("transform", Transform());
    } else if (entry.value->is_string()) {
      relative = entry.as<std::string>();
    } else {
      throw SceneError(entry.where, "expected a file name or an object with 'file', got " +
                                        jsonTypeName(*entry.value));
    }
    fs::path path = fs::path(relative).is_absolute() ? fs::path(relative) : folder / relative;
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".gltf" && ext != ".glb")
      throw SceneError(at, "expected a .gltf or .glb file, got '" + relative + "'");
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw SceneError(at, "file not found: " + path.string());
    loadGltf(path.string(), scene, transform);
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Entry points
// ---------------------------------------------------------------------------------------------

void applySceneJsonText(std::string_view text, const std::string& file, SceneJsonKind kind,
                        SceneDescription* scene) {
  nlohmann::json doc = parseJson(text, file);
  JsonReader root(doc, {file, ""});
  if (kind == SceneJsonKind::Scene)
    loadGltfList(root, file, scene);
  else if (root.has("gltf"))
    throw SceneError(root.where("gltf"), "only a .json scene may list glTF files");

  readCameras(root, scene);
  readLights(root, scene);
  readTextures(root, file, scene);
  readMaterials(root, scene);
  readObjects(root, file, scene);
  JsonReader* render = root.optionalObject("render");
  if (render) readRender(*render, &scene->render);
  // Unknown keys first: a misspelt section would otherwise surface as a confusing
  // cross-reference error below.
  root.finish();
  if (render) checkRenderCamera(*render, *scene);
}

void applySceneJsonFile(const std::string& path, SceneJsonKind kind, SceneDescription* scene) {
  applySceneJsonText(readTextFile(path), path, kind, scene);
}

std::string defaultSidecarPath(const std::string& gltfPath) {
  return fs::path(gltfPath).replace_extension(".glint.json").string();
}

}  // namespace glint
