// glint — reading participating media from the sidecar JSON (schema: scenes/README.md, media).
#include "scenes/sidecar_media.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "geometry/shapes/box.h"
#include "scenes/paths.h"
#include "scenes/sidecar_objects.h"
#include "scenes/vdb_file.h"
#include "scenes/vol_file.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

// A medium's region: a solid with finite bounds (Shape::isSolid, so convex; the plane's
// half-space is unbounded).
bool isBoundedSolid(const Shape& shape) { return shape.isSolid() && !isUnbounded(shape.bounds()); }

const std::vector<std::pair<std::string, DensityType>> kDensityTypes = {
    {"constant", DensityType::Constant}, {"grid", DensityType::Grid},
    {"noise", DensityType::Noise},       {"exponential", DensityType::Exponential},
    {"vdb", DensityType::Vdb},
};

// A coefficient: one number (grey) or [r, g, b], either possibly keyframed; >= 0.
Rgb readCoefficient(JsonReader& r, std::string_view key) {
  const nlohmann::json* v = r.take(key);
  if (!v) return {0, 0, 0};
  bool grey = v->is_number();
  if (isKeyframes(*v)) {
    const nlohmann::json& keys = (*v)["keys"];
    grey = keys.is_array() && !keys.empty() && keys[0].is_array() && keys[0].size() == 2 &&
           keys[0][1].is_number();
  }
  if (grey) {
    const float x = r.value<float>(*v, r.where(key), kNonNegative);
    return {x, x, x};
  }
  return r.value<Vec3f>(*v, r.where(key), kNonNegative);
}

void readGrid(JsonReader& d, const std::string& file, MediumDesc* m) {
  if (d.has("file") == d.has("values"))
    throw SceneError(d.where(),
                     "a grid density has either 'file' (.vol) or 'values' with "
                     "'resolution'");
  if (d.has("file")) {
    const std::string relative = d.get<std::string>("file");
    const fs::path path = existingScenePath(relative, file, d.where("file"));
    VolumeGrid grid;
    try {
      grid = readVolFile(path.string());
    } catch (const SceneError& e) {
      // "scene.json: /media/0/density/file: /abs/smoke.vol: truncated header": where the
      // sidecar names the file, then the file and what is wrong in it.
      throw SceneError(d.where("file"), e.what());
    }
    m->gridRes[0] = grid.nx, m->gridRes[1] = grid.ny, m->gridRes[2] = grid.nz;
    m->gridValues = std::move(grid.values);
    return;
  }
  std::vector<JsonItem> res = d.array("resolution");
  if (res.size() != 3) throw SceneError(d.where("resolution"), "expected [nx, ny, nz]");
  size_t count = 1;
  for (int a = 0; a < 3; ++a) {
    m->gridRes[a] = res[size_t(a)].as<int>({.ge = 1, .le = 4096});
    count *= size_t(m->gridRes[a]);
  }
  std::vector<JsonItem> values = d.array("values");
  if (values.size() != count)
    throw SceneError(d.where("values"), "expected " + std::to_string(count) +
                                            " values (nx * ny * nz), got " +
                                            std::to_string(values.size()));
  for (const JsonItem& v : values) m->gridValues.push_back(v.as<float>(kNonNegative));
}

// "smoke_####.vdb" for `frame`: the run of '#' in the file name replaced by the frame number,
// zero-padded to the run's length (as `glint render --frames` names its outputs); a name
// without '#' as it is.
std::string framePath(const std::string& written, long long frame, const SourceLocation& where) {
  const size_t slash = written.find_last_of('/');
  const size_t nameStart = slash == std::string::npos ? 0 : slash + 1;
  const size_t first = written.find('#', nameStart);
  if (written.find('#') < nameStart)
    throw SceneError(where, "'#' (the frame number) belongs in the file name, not a folder");
  if (first == std::string::npos) return written;
  const size_t last = written.find_first_not_of('#', first);
  const size_t width = (last == std::string::npos ? written.size() : last) - first;
  if (last != std::string::npos && written.find('#', last) != std::string::npos)
    throw SceneError(where, "one run of '#' stands for the frame number; this name has two");
  std::string number = std::to_string(frame);
  if (number.size() < width) number.insert(0, width - number.size(), '0');
  return written.substr(0, first) + number + written.substr(first + width);
}

// A VDB medium: its file (one per frame for a '#' pattern), grids, scales and emission.
void readVdb(JsonReader& d, const std::string& file, float fps, MediumDesc* m) {
  const std::string written = d.get<std::string>("file");
  // The frame of the scene time: round(time x frame_rate) + frame_offset.
  const float rate = d.get<float>("frame_rate", fps, kPositive);
  const int offset = d.get<int>("frame_offset", 0);
  const long long frame = std::llround(d.time().value_or(0.0) * double(rate)) + offset;
  const bool sequence = written.find('#') != std::string::npos;
  if (sequence && frame < 0)
    throw SceneError(d.where("frame_offset"),
                     "the scene time gives frame " + std::to_string(frame) + " (must be >= 0)");
  const std::string relative = framePath(written, frame, d.where("file"));
  const fs::path path = existingScenePath(relative, file, d.where("file"));
  VdbRequest request;
  request.where = d.where("file");
  request.density = {d.get<std::string>("grid", "density"), d.where("grid")};
  if (d.has("temperature_grid"))
    request.temperature =
        VdbGridRequest{d.get<std::string>("temperature_grid"), d.where("temperature_grid")};
  if (d.has("flame_grid"))
    request.flame = VdbGridRequest{d.get<std::string>("flame_grid"), d.where("flame_grid")};
  if (d.has("color_grid")) {
    // One vec3s grid's name, or three float grids' (red, green, blue).
    if (d.json()["color_grid"].is_array()) {
      const std::vector<JsonItem> names = d.array("color_grid");
      if (names.size() != 3)
        throw SceneError(d.where("color_grid"),
                         "must be one vec3s grid's name or three float grids' (red, green, blue)");
      for (const JsonItem& n : names) request.color.push_back({n.as<std::string>(), n.where});
    } else {
      request.color.push_back({d.get<std::string>("color_grid"), d.where("color_grid")});
    }
  }
  m->colorTintsAlbedo = d.oneOf("color_mode", {"scattering", "albedo"}, "scattering") == "albedo";
  request.colorDensityWeighted = d.get<bool>("color_density_weighted", false);
  if ((m->colorTintsAlbedo || request.colorDensityWeighted) && request.color.empty())
    throw SceneError(d.where(m->colorTintsAlbedo ? "color_mode" : "color_density_weighted"),
                     "needs a color_grid");
  request.kelvin.scale = d.get<float>("temperature_scale", 1.0f, kNonNegative);
  request.kelvin.offset = d.get<float>("temperature_offset", 0.0f);
  request.kelvin.cutoff = d.get<float>("temperature_cutoff", 0.0f, kNonNegative);
  request.majorantCells = d.get<int>("majorant_cells", 16, {.ge = 1, .le = 1024});
  m->vdbScale = d.get<float>("scale", 1.0f, kNonNegative);
  m->blackbodyIntensity =
      d.get<float>("blackbody_intensity", request.temperature ? 1.0f : 0.0f, kNonNegative);
  m->flameStrength = d.get<float>("flame_strength", request.flame ? 1.0f : 0.0f, kNonNegative);
  m->flameColor = d.get<Vec3f>("flame_color", Vec3f{1, 1, 1}, kNonNegative);
  m->vdb = readVdbFile(path.string(), request);
}

void readDensity(JsonReader& d, const std::string& file, float fps, MediumDesc* m) {
  m->density = d.oneOf<DensityType>("type", kDensityTypes);
  switch (m->density) {
    case DensityType::Constant:
      m->value = d.get<float>("value", 1.0f, kNonNegative);
      break;
    case DensityType::Grid:
      readGrid(d, file, m);
      break;
    case DensityType::Noise:
      m->noiseScale = d.get<float>("scale", 1.0f, kPositive);
      m->noiseOctaves = d.get<int>("octaves", 4, {.ge = 1, .le = 16});
      m->noiseThreshold = d.get<float>("threshold", 0.0f, {.ge = 0, .lt = 1});
      m->noiseSeed = d.get<uint64_t>("seed", uint64_t(0));
      m->noiseOffset = d.get<Vec3f>("offset", Vec3f{0, 0, 0});
      break;
    case DensityType::Exponential:
      m->up = d.get<Vec3f>("up", Vec3f{0, 1, 0});
      if (m->up == Vec3f{}) throw SceneError(d.where("up"), "must not be zero");
      m->up = normalize(m->up);
      m->falloff = d.get<float>("falloff", 1.0f, kNonNegative);
      m->h0 = d.get<float>("height", 0.0f);
      break;
    case DensityType::Vdb:
      readVdb(d, file, fps, m);
      break;
  }
}

int objectByName(const SceneDescription& scene, const std::string& name,
                 const SourceLocation& where) {
  std::vector<std::string> names;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name == name) return int(i);
    names.push_back(scene.objects[i].name);
  }
  std::string message = "no object named '" + name + "'";
  if (std::string guess = closestMatch(name, names); !guess.empty())
    message += "; did you mean '" + guess + "'?";
  throw SceneError(where, message);
}

// A VDB medium fills the box of its grids' active voxels (VdbVolume::bounds) in the file's
// world space, which the medium's "transform" and "animation" place in the scene.
void placeVdb(JsonReader& r, MediumDesc* m) {
  if (m->region != MediumDesc::Region::Scene)
    throw SceneError(r.where(m->region == MediumDesc::Region::Shape ? "region" : "object"),
                     "a vdb medium fills the box of its grids' active voxels: it takes "
                     "'transform' and 'animation', not a region or an object");
  m->region = MediumDesc::Region::Shape;
  m->shape = std::make_shared<Box>(m->vdb->bounds.lower, m->vdb->bounds.upper);
  m->worldFromRegion = r.get<Transform>("transform", Transform());
  if (std::optional<NodeDesc> node = readAnimation(r, m->name))
    m->worldFromRegion = worldFromNode({*node}, 0, r.time().value_or(0.0)) * m->worldFromRegion;
}

MediumDesc readMedium(JsonReader& r, const std::string& file, const SceneDescription& scene) {
  MediumDesc m;
  m.where = r.where();
  m.name = r.get<std::string>("name", "");
  if (r.has("region") && r.has("object"))
    throw SceneError(r.where(),
                     "a medium has 'region' (a solid), 'object' (an object's solid) "
                     "or neither (the whole scene), not both");
  if (JsonReader* region = r.optionalObject("region")) {
    m.region = MediumDesc::Region::Shape;
    const ShapeKind& kind = *findShapeKind(region->oneOf("type", shapeNames()));
    m.shape = readShape(*region, kind);
    if (!isBoundedSolid(*m.shape)) {
      // The type itself is wrong when no parameters could make it a bounded solid.
      const bool typeIsWrong = kind.csgKeys.empty() || isUnbounded(m.shape->bounds());
      throw SceneError(typeIsWrong ? region->where("type") : region->where(),
                       "a region must be a bounded closed solid (sphere, box, capped cylinder "
                       "or cone), not " +
                           std::string(typeIsWrong ? "a " : "an open ") + kind.name);
    }
    m.worldFromRegion = region->get<Transform>("transform", Transform());
  } else if (r.has("object")) {
    m.region = MediumDesc::Region::Object;
    m.object = objectByName(scene, r.get<std::string>("object"), r.where("object"));
    const ObjectDesc& obj = scene.objects[size_t(m.object)];
    if (obj.kind != ObjectKind::Shape || !isBoundedSolid(*obj.shape))
      throw SceneError(r.where("object"), "object '" + obj.name +
                                              "' is not a bounded convex solid (sphere, box, "
                                              "capped cylinder or cone)");
  }
  m.sigmaA = readCoefficient(r, "sigma_a");
  m.sigmaS = readCoefficient(r, "sigma_s");
  m.emission = readCoefficient(r, "emission");
  m.g = r.get<float>("g", 0.0f, {.gt = -1, .lt = 1});
  m.heroTracking = r.oneOf("chromatic_tracking", {"spectral_mis", "max_channel"}, "spectral_mis") ==
                   "spectral_mis";
  if (JsonReader* d = r.optionalObject("density"))
    readDensity(*d, file, float(scene.render.fps), &m);
  if (m.density == DensityType::Vdb) placeVdb(r, &m);
  return m;
}

}  // namespace

const std::string& densityTypeName(DensityType type) {
  for (const auto& [name, t] : kDensityTypes)
    if (t == type) return name;
  throw std::logic_error("densityTypeName: a density type without a sidecar name");
}

void readMedia(JsonReader& root, const std::string& file, SceneDescription* scene) {
  for (JsonReader* r : root.objects("media")) scene->media.push_back(readMedium(*r, file, *scene));
}

}  // namespace glint
