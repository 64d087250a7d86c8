// glint — the glint JSON schema (sidecars and .json scenes), read into a SceneDescription.
#include "scenes/sidecar.h"

#include <filesystem>

#include "geometry/accel/accelerator.h"
#include "renderer/integrator.h"
#include "renderer/light_sampler.h"
#include "scenes/gltf_loader.h"
#include "scenes/json_reader.h"
#include "scenes/json_util.h"
#include "scenes/paths.h"
#include "scenes/sidecar_lights.h"
#include "scenes/sidecar_materials.h"
#include "scenes/sidecar_media.h"
#include "scenes/sidecar_objects.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

// Names accepted by the render block (accelerators and light samplers come from their
// factories).
const std::vector<std::string> kVolumeModes = {"emission", "single", "multiple"};
const std::vector<std::string> kVolumeEstimators = {"march", "track"};
const std::vector<std::string> kFilters = {"box", "tent", "gaussian"};
const std::vector<std::string> kToneMapOperators = {"none", "ward"};

float radians(float degrees) { return degrees * (kPi / 180.0f); }

// ---------------------------------------------------------------------------------------------
// render
// ---------------------------------------------------------------------------------------------

// "integrator": a name, or an object with "type" and the integrator's settings.
void readIntegrator(JsonReader& r, IntegratorSettings* s) {
  if (!r.has("integrator")) return;
  if (r.json().at("integrator").is_string()) {
    s->type = r.oneOf("integrator", integratorNames(), s->type);
    return;
  }
  JsonReader& i = r.object("integrator");
  s->type = i.oneOf("type", integratorNames(), s->type);
  s->maxDepth = i.get<int>("max_depth", s->maxDepth, kNonNegative);
  s->rrDepth = i.get<int>("rr_depth", s->rrDepth, kNonNegative);
  s->lightSampler = i.oneOf("light_sampler", lightSamplerNames(), s->lightSampler);
  s->volume = i.oneOf("volume", kVolumeModes, s->volume);
  s->volumeEstimator = i.oneOf("volume_estimator", kVolumeEstimators, s->volumeEstimator);
  s->volumeStep = i.get<float>("volume_step", s->volumeStep, kNonNegative);
  s->wholeSegmentEmission = i.get<bool>("whole_segment_emission", s->wholeSegmentEmission);
  s->glassShadows = i.get<bool>("glass_shadows", s->glassShadows);
  s->minWeight = i.get<float>("min_weight", s->minWeight, {.ge = 0, .le = 1});
  s->vplPaths = i.get<int>("vpl_paths", s->vplPaths, kPositive);
  s->vplClamp = i.get<float>("vpl_clamp", s->vplClamp, kNonNegative);
  s->vplShadowShare = i.get<float>("vpl_shadow_share", s->vplShadowShare, {.ge = 0, .le = 1});
}

// A "shutter": [open, close], seconds from the frame time (a camera's or the render block's).
std::optional<Vec2f> readShutter(JsonReader& r) {
  auto shutter = r.optional<Vec2f>("shutter");
  if (shutter && shutter->x > shutter->y)
    throw SceneError(r.where("shutter"),
                     "the shutter must open before it closes ([open, close] "
                     "with open <= close, seconds from the frame time)");
  return shutter;
}

// Fills `s` from the render block; a missing key keeps the value already there.
void readRender(JsonReader& r, RenderSettings* s) {
  if (auto width = r.optional<int>("width", kPositive)) s->width = width;
  if (auto height = r.optional<int>("height", kPositive)) s->height = height;
  s->spp = r.get<int>("spp", s->spp, kPositive);
  if (JsonReader* a = r.optionalObject("adaptive")) {
    s->adaptive.threshold = a->get<float>("threshold", s->adaptive.threshold, kNonNegative);
    s->adaptive.contrast = a->get<float>("contrast", s->adaptive.contrast, {.ge = 0, .le = 1});
    s->adaptive.minSpp = a->get<int>("min_spp", s->adaptive.minSpp, {.ge = 2});
    s->adaptive.subdivide =
        a->get<int>("subdivide", s->adaptive.subdivide, {.ge = 0, .le = kMaxSubdivision});
    s->adaptive.jitter = a->get<float>("jitter", s->adaptive.jitter, {.ge = 0, .le = 1});
  }
  s->seed = r.get<uint64_t>("seed", s->seed);
  s->threads = r.get<int>("threads", s->threads, kNonNegative);
  s->accel = r.oneOf("accel", acceleratorNames(), s->accel);
  s->camera = r.get<std::string>("camera", s->camera);
  readIntegrator(r, &s->integrator);
  // The scene time was taken from here before anything else was read (sceneTime below).
  s->time = r.get<double>("time", s->time);
  s->fps = r.get<double>("fps", s->fps, kPositive);
  if (auto shutter = readShutter(r)) s->shutter = std::array<double, 2>{shutter->x, shutter->y};
  if (JsonReader* f = r.optionalObject("filter")) {
    s->filter.type = f->oneOf("type", kFilters, s->filter.type);
    s->filter.radius = f->get<float>("radius", s->filter.radius, kPositive);
  }
  s->background = r.get<Rgb>("background", s->background, kNonNegative);
  s->defaultLight = r.get<bool>("default_light", s->defaultLight);
  s->variant = r.get<std::string>("variant", s->variant);
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
  std::vector<std::string> names;
  for (const CameraDesc& c : scene.cameras) {
    if (c.name == name) return;
    names.push_back(c.name);
  }
  const std::string available = quotedNames(names);
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

// ---------------------------------------------------------------------------------------------
// cameras
// ---------------------------------------------------------------------------------------------

// Thin lens and shutter: "aperture", "focus_distance", "blades", "blade_rotation",
// "shutter". `lookAtDistance` is the distance from position to look_at (0 when the camera is
// placed by a transform): the focus distance when an aperture is given without one.
void readLensAndShutter(JsonReader& r, float lookAtDistance, CameraDesc* cam) {
  cam->apertureRadius = r.get<float>("aperture", cam->apertureRadius, kNonNegative);
  if (auto focus = r.optional<float>("focus_distance", kPositive))
    cam->focusDistance = *focus;
  else if (cam->apertureRadius > 0 && cam->focusDistance <= 0 && lookAtDistance > 0)
    cam->focusDistance = lookAtDistance;
  if (cam->apertureRadius > 0 && cam->focusDistance <= 0)
    throw SceneError(r.where("aperture"),
                     "a camera with an aperture needs 'focus_distance' (or 'position' and "
                     "'look_at', whose distance it then focuses at)");
  cam->apertureBlades = r.get<int>("blades", cam->apertureBlades, kNonNegative);
  if (cam->apertureBlades == 1 || cam->apertureBlades == 2)
    throw SceneError(r.where("blades"), "must be 0 (a round aperture) or >= 3 (a polygon)");
  if (auto degrees = r.optional<float>("blade_rotation")) cam->apertureRotation = radians(*degrees);
  if (auto shutter = readShutter(r)) cam->shutterOpen = shutter->x, cam->shutterClose = shutter->y;
}

// Places `item` under its "animation" when it has one: world(t) = animation(t) · `placed`.
// Returns the node index (or -1) and writes the placement at the scene time to `world`.
int animate(JsonReader& r, const std::string& name, const Transform& placed,
            SceneDescription* scene, Transform* world) {
  std::optional<NodeDesc> node = readAnimation(r, name);
  if (!node) return -1;
  scene->nodes.push_back(*node);
  int index = int(scene->nodes.size()) - 1;
  *world = worldFromNode(scene->nodes, index, r.time().value_or(0.0)) * placed;
  return index;
}

// A camera entry. `base` is the existing camera of the same name when the entry gives no
// placement: then only the keys given change it (a lens on a glTF camera, for instance).
CameraDesc readCamera(JsonReader& r, const CameraDesc* base, SceneDescription* scene) {
  CameraDesc cam;
  cam.yfov = radians(40);
  if (base) cam = *base;
  cam.where = r.where();
  cam.name = r.get<std::string>("name", "");
  cam.type = r.oneOf<CameraType>(
      "type",
      {{"perspective", CameraType::Perspective}, {"orthographic", CameraType::Orthographic}},
      cam.type);
  if (cam.type == CameraType::Perspective) {
    if (auto fov = r.optional<float>("yfov_degrees", {.gt = 0, .lt = 180}))
      cam.yfov = radians(*fov);
    cam.aspectRatio = r.get<float>("aspect_ratio", cam.aspectRatio, kPositive);
  } else {
    cam.xmag = r.get<float>("xmag", cam.xmag, kPositive);
    cam.ymag = r.get<float>("ymag", cam.ymag, kPositive);
  }
  cam.znear = r.get<float>("znear", cam.znear, kNonNegative);
  cam.zfar = r.get<float>("zfar", cam.zfar, kPositive);
  if (cam.znear >= cam.zfar)
    throw SceneError(r.where("znear"), "must be < zfar (znear " + std::to_string(cam.znear) +
                                           ", zfar " + std::to_string(cam.zfar) + ")");
  float lookAtDistance = 0;
  if (base) {
    if (r.has("animation"))
      throw SceneError(r.where("animation"),
                       "an 'animation' needs the camera's own placement ('position' and "
                       "'look_at', or 'transform')");
  } else {
    if (usesTransform(r, {"position", "look_at", "up"})) {
      cam.worldFromCamera = r.get<Transform>("transform");
    } else {
      if (!r.has("position") || !r.has("look_at"))
        throw SceneError(r.where(), "a camera needs 'position' and 'look_at', or a 'transform'");
      Vec3f eye = r.get<Vec3f>("position");
      Vec3f target = r.get<Vec3f>("look_at");
      Vec3f up = r.get<Vec3f>("up", Vec3f{0, 1, 0});
      cam.worldFromCamera = aimAlong(r, eye, target - eye, up, "look_at", "up");
      lookAtDistance = distance(eye, target);
    }
    cam.transformNode = -1;
    cam.nodeFromCamera = Transform();
    Transform placed = cam.worldFromCamera;
    if (int node = animate(r, cam.name, placed, scene, &cam.worldFromCamera); node >= 0)
      cam.transformNode = node, cam.nodeFromCamera = placed;
  }
  readLensAndShutter(r, lookAtDistance, &cam);
  return cam;
}

// A camera named like an existing one replaces it; others are added.
void readCameras(JsonReader& root, SceneDescription* scene) {
  std::vector<std::pair<std::string, std::string>> seen;  // name, pointer
  for (JsonReader* r : root.objects("cameras")) {
    const CameraDesc* base = nullptr;
    bool placed = r->has("transform") || r->has("position") || r->has("look_at") || r->has("up");
    if (!placed && r->has("name") && r->json()["name"].is_string())
      for (const CameraDesc& existing : scene->cameras)
        if (existing.name == r->json()["name"].get<std::string>()) base = &existing;
    CameraDesc cam = readCamera(*r, base, scene);
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

LightDesc readLight(JsonReader& r, SceneDescription* scene) {
  LightDesc light;
  light.where = r.where();
  light.name = r.get<std::string>("name", "");
  light.type = r.oneOf<LightType>("type", {{"point", LightType::Point},
                                           {"spot", LightType::Spot},
                                           {"directional", LightType::Directional},
                                           {"quad", LightType::Quad},
                                           {"disk", LightType::Disk},
                                           {"sphere", LightType::Sphere},
                                           {"projective", LightType::Projective}});
  light.color = r.get<Rgb>("color", light.color, kNonNegative);
  light.intensity = r.get<float>("intensity", light.intensity, kNonNegative);
  light.castsShadows = r.get<bool>("cast_shadows", light.castsShadows);
  if (light.type == LightType::Point || light.type == LightType::Spot)
    light.range = r.get<float>("range", light.range, kNonNegative);

  if (isSidecarOnlyLight(light.type)) readSidecarLight(r, *scene, &light);
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
    default:  // read above
      break;
  }
  Transform placed = light.worldFromLight;
  if (int node = animate(r, light.name, placed, scene, &light.worldFromLight); node >= 0)
    light.transformNode = node, light.nodeFromLight = placed;
  return light;
}

void readLights(JsonReader& root, SceneDescription* scene) {
  for (JsonReader* r : root.objects("lights")) {
    LightDesc light = readLight(*r, scene);
    scene->lights.push_back(light);
  }
}

// ---------------------------------------------------------------------------------------------
// gltf (only in a .json scene)
// ---------------------------------------------------------------------------------------------

// Reads the "gltf" list; loads the files only when `load` (SceneLoader loads them once and
// then re-applies the rest of the scene per frame).
void loadGltfList(JsonReader& root, const std::string& file, SceneDescription* scene, bool load) {
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
    fs::path path = resolveScenePath(relative, file);
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".gltf" && ext != ".glb")
      throw SceneError(at, "expected a .gltf or .glb file, got '" + relative + "'");
    if (!load) continue;
    loadGltf(existingScenePath(relative, file, at).string(), scene, transform);
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Entry points
// ---------------------------------------------------------------------------------------------

double sceneTime(const nlohmann::json& doc, const std::string& file, const SceneDescription& scene,
                 const SceneJsonOptions& options) {
  if (options.time) return *options.time;
  if (doc.is_object() && doc.contains("render") && doc["render"].is_object() &&
      doc["render"].contains("time")) {
    SourceLocation at{file, "/render/time"};
    const nlohmann::json& t = doc["render"]["time"];
    if (isKeyframes(t)) throw SceneError(at, "the scene time itself cannot be keyframed");
    return readValue<double>(t, at);
  }
  return scene.render.time;
}

void applySceneJson(const nlohmann::json& doc, const std::string& file, SceneJsonKind kind,
                    SceneDescription* scene, const SceneJsonOptions& options) {
  // Every keyframed value is evaluated at one time, known before anything else is read.
  double time = sceneTime(doc, file, *scene, options);
  JsonReader root(doc, {file, ""}, time);
  if (kind == SceneJsonKind::Scene)
    loadGltfList(root, file, scene, options.loadGltf);
  else if (root.has("gltf"))
    throw SceneError(root.where("gltf"), "only a .json scene may list glTF files");

  readCameras(root, scene);
  readTextures(root, file, scene);  // before lights and materials, which name textures
  readLights(root, scene);
  readEnvironment(root, file, scene);
  readMaterials(root, scene);
  readObjects(root, file, scene);
  readMedia(root, file, scene);
  JsonReader* render = root.optionalObject("render");
  if (render) readRender(*render, &scene->render);
  scene->render.time = time;
  // Unknown keys first: a misspelt section would otherwise surface as a confusing
  // cross-reference error below.
  root.finish();
  if (render) checkRenderCamera(*render, *scene);
  evaluatePlacements(scene, time);
}

void applySceneJsonText(std::string_view text, const std::string& file, SceneJsonKind kind,
                        SceneDescription* scene, const SceneJsonOptions& options) {
  applySceneJson(parseSceneJson(text, file), file, kind, scene, options);
}

void applySceneJsonFile(const std::string& path, SceneJsonKind kind, SceneDescription* scene,
                        const SceneJsonOptions& options) {
  applySceneJsonText(readTextFile(path), path, kind, scene, options);
}

void readRenderBlock(JsonReader& r, SceneDescription* scene) {
  readRender(r, &scene->render);
  checkRenderCamera(r, *scene);
}

void loadSceneGltfList(const nlohmann::json& doc, const std::string& file,
                       SceneDescription* scene) {
  JsonReader root(doc, {file, ""});
  loadGltfList(root, file, scene, true);
}

std::string defaultSidecarPath(const std::string& gltfPath) {
  return fs::path(gltfPath).replace_extension(".glint.json").string();
}

}  // namespace glint
