// glint tests — the invariance net's scene rewriting, rendering and comparison (invariance.h).
#include "invariance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "image/output.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/description.h"
#include "scenes/sidecar.h"

namespace glint::invariance {

V3 normalized(V3 v) { return v * (1 / std::sqrt(dot(v, v))); }

V3 toV3(const Json& j) {
  if (!j.is_array() || j.size() != 3)
    throw std::runtime_error("expected a 3-vector, got " + j.dump());
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

Json toJson(V3 v) { return Json::array({v.x, v.y, v.z}); }

// ---------------------------------------------------------------------------------------------
// Similarity maps
// ---------------------------------------------------------------------------------------------

V3 Similarity::rotate(V3 v) const {
  return {R[0][0] * v.x + R[0][1] * v.y + R[0][2] * v.z,
          R[1][0] * v.x + R[1][1] * v.y + R[1][2] * v.z,
          R[2][0] * v.x + R[2][1] * v.y + R[2][2] * v.z};
}

double Similarity::handedness() const {
  const double d = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) -
                   R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
                   R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
  return d < 0 ? -1 : 1;
}

bool Similarity::turns() const {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (R[i][j] != (i == j ? 1 : 0)) return true;
  return false;
}

Similarity identity() {
  Similarity x;
  x.name = "identity";
  x.op = {{"translate", Json::array({0, 0, 0})}};
  return x;
}

Similarity translation(V3 d) {
  Similarity x;
  x.t = d;
  x.op = {{"translate", toJson(d)}};
  return x;
}

Similarity scaling(double s) {
  Similarity x;
  x.s = s;
  x.op = x.linearOp = {{"scale", s}};
  return x;
}

Similarity rotation(V3 axis, double degrees) {
  Similarity x;
  const V3 a = normalized(axis);
  const double th = degrees * std::numbers::pi / 180, c = std::cos(th), s = std::sin(th), k = 1 - c;
  x.R = {{{c + a.x * a.x * k, a.x * a.y * k - a.z * s, a.x * a.z * k + a.y * s},
          {a.y * a.x * k + a.z * s, c + a.y * a.y * k, a.y * a.z * k - a.x * s},
          {a.z * a.x * k - a.y * s, a.z * a.y * k + a.x * s, c + a.z * a.z * k}}};
  x.op = x.linearOp = {{"rotate", {{"axis", toJson(axis)}, {"degrees", degrees}}}};
  return x;
}

Similarity reflection(V3 n) {
  Similarity x;
  const V3 u = normalized(n);
  const double c[3] = {u.x, u.y, u.z};
  Json rows = Json::array();
  for (int i = 0; i < 3; ++i) {
    Json row = Json::array();
    for (int j = 0; j < 3; ++j) {
      x.R[size_t(i)][size_t(j)] = (i == j ? 1 : 0) - 2 * c[i] * c[j];
      row.push_back(x.R[size_t(i)][size_t(j)]);
    }
    row.push_back(0);
    rows.push_back(row);
  }
  rows.push_back(Json::array({0, 0, 0, 1}));
  x.op = x.linearOp = {{"matrix", rows}};
  return x;
}

Similarity randomRotation(uint64_t seed) {
  uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1;
  auto uniform = [&] {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) * 0x1p-53;
  };
  const double z = 2 * uniform() - 1, phi = 2 * std::numbers::pi * uniform();
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  // Round the axis and angle to what the JSON prints, so the map is exactly the one glint reads.
  auto round6 = [](double v) { return std::round(v * 1e6) / 1e6; };
  const V3 axis{round6(r * std::cos(phi)), round6(r * std::sin(phi)), round6(z)};
  return rotation(axis, round6(20 + 320 * uniform()));
}

// ---------------------------------------------------------------------------------------------
// Rewriting a scene
// ---------------------------------------------------------------------------------------------

namespace {

struct Context {
  const Similarity& x;
  Placement mode;
  const SceneFacts& facts;
  std::vector<std::string>* notes;
  const Json& scene;                  // the original, for looking up materials and textures
  std::set<std::string> shapeEdited;  // objects moved by their shape keys (Edit mode)
  void note(const std::string& line) {
    if (std::find(notes->begin(), notes->end(), line) == notes->end()) notes->push_back(line);
  }
};

// Applies f to a value, or to every key of a keyframed value ({"keys": [[t, v], ...]}).
template <class F>
void mapKeyed(Json& v, F f) {
  if (v.is_object() && v.contains("keys")) {
    for (Json& key : v["keys"]) f(key[1]);
  } else {
    f(v);
  }
}

void movePoint(Json& obj, const char* key, const Similarity& x) {
  if (obj.contains(key)) mapKeyed(obj[key], [&](Json& v) { v = toJson(x.point(toV3(v))); });
}
void moveVector(Json& obj, const char* key, const Similarity& x) {
  if (obj.contains(key)) mapKeyed(obj[key], [&](Json& v) { v = toJson(x.vector(toV3(v))); });
}
void turnDirection(Json& obj, const char* key, const Similarity& x) {
  if (obj.contains(key)) mapKeyed(obj[key], [&](Json& v) { v = toJson(x.rotate(toV3(v))); });
}
// Multiplies a number or a colour (keyframed or not) by f.
void multiply(Json& obj, const char* key, double f) {
  if (!obj.contains(key) || f == 1) return;
  mapKeyed(obj[key], [&](Json& v) {
    if (v.is_number()) {
      v = v.get<double>() * f;
    } else {
      for (Json& c : v) c = c.get<double>() * f;
    }
  });
}

// A transform as a list of operations (a matrix becomes one {"matrix": M}).
Json opList(const Json& transform) {
  if (transform.is_null()) return Json::array();
  if (!transform.is_array()) throw std::runtime_error("unexpected transform " + transform.dump());
  if (!transform.empty() && (transform[0].is_number() || transform[0].is_array()))
    return Json::array({Json{{"matrix", transform}}});
  return transform;
}

bool hasTransform(const Json& obj) {
  return obj.contains("transform") && !opList(obj["transform"]).empty();
}

void appendOp(Json& obj, const Json& op) {
  if (op.is_null()) return;
  Json ops = opList(obj.value("transform", Json()));
  ops.push_back(op);
  obj["transform"] = ops;
}

// Edit mode: the translation added to the transform's last `translate`, or a new one.
void editTranslate(Json& obj, V3 d) {
  Json ops = opList(obj.value("transform", Json()));
  if (!ops.empty() && ops.back().is_object() && ops.back().size() == 1 &&
      ops.back().contains("translate"))
    ops.back()["translate"] = toJson(toV3(ops.back()["translate"]) + d);
  else
    ops.push_back({{"translate", toJson(d)}});
  obj["transform"] = ops;
}

// The map without its translation (for animated items: their translation goes to the track).
Similarity linearPart(const Similarity& x) {
  Similarity l = x;
  l.t = {};
  l.op = x.linearOp;
  return l;
}

// An item under an `animation`: world(t) = T(t) R(t) S(t) placed. With x = (s Q, t0),
// x world(t) = x(T(t)) . (Q R(t) Q^-1) . S(t) . (s Q placed) when S(t) is uniform: the
// translation keys are mapped as points, the rotation axis turned (and the angle reversed by a
// reflection), and the linear part of x goes onto the static placement (the caller's job).
void moveAnimation(Json& anim, const Similarity& x) {
  if (anim.contains("translation")) {
    mapKeyed(anim["translation"], [&](Json& v) { v = toJson(x.point(toV3(v))); });
  } else if (x.moves()) {
    anim["translation"] = {{"keys", Json::array({Json::array({0, toJson(x.t)})})}};
  }
  if (anim.contains("rotation") && x.turns()) {
    Json& r = anim["rotation"];
    if (!r.contains("axis"))
      throw std::runtime_error("quaternion rotation tracks are not rewritten by the net");
    r["axis"] = toJson(x.rotate(toV3(r["axis"])));
    if (x.handedness() < 0)
      for (Json& key : r["keys"]) key[1] = -key[1].get<double>();
  }
  if (anim.contains("scale") && x.turns())
    mapKeyed(anim["scale"], [&](Json& v) {
      if (!v.is_number()) throw std::runtime_error("a non-uniform scale track cannot be turned");
    });
}

// Textures named by a material (colour keys and bump), and whether one reads object space.
const Json* findNamed(const Json& scene, const char* section, const std::string& name) {
  if (!scene.contains(section)) return nullptr;
  for (const Json& e : scene[section])
    if (e.value("name", "") == name) return &e;
  return nullptr;
}

bool textureReadsObjectSpace(const Json& tex) {
  const std::string type = tex.value("type", "");
  std::string space;
  if (tex.contains("mapping")) space = tex["mapping"].value("space", "");
  if (space.empty())
    space = type == "image" || (type == "checker" && !tex.value("solid", false)) ? "uv"
            : type == "random"                                                   ? "uv"
                                                                                 : "object";
  return space == "object";
}

bool materialReadsObjectSpace(const Json& scene, const std::string& name) {
  const Json* m = findNamed(scene, "materials", name);
  if (!m) return false;  // the default material, or a glTF one
  if (m->contains("snow")) return true;
  for (const auto& [key, value] : m->items()) {
    std::string texture;
    if (value.is_string() && key != "name" && key != "type" && key != "alpha_mode" &&
        key != "mode" && key != "shading")
      texture = value.get<std::string>();
    if ((key == "bump" || key == "normal_map") && value.contains("texture"))
      texture = value["texture"].get<std::string>();
    if (texture.empty()) continue;
    if (const Json* t = findNamed(scene, "textures", texture); t && textureReadsObjectSpace(*t))
      return true;
  }
  return false;
}

bool nodeReadsObjectSpace(const Json& scene, const Json& node) {
  if (node.contains("material") && materialReadsObjectSpace(scene, node["material"])) return true;
  if (node.contains("children"))
    for (const Json& c : node["children"])
      if (nodeReadsObjectSpace(scene, c)) return true;
  if (node.contains("tree")) return nodeReadsObjectSpace(scene, node["tree"]);
  return false;
}

// Edit mode: a primitive moved by its own position keys; those without one get a transform.
void editShapeKeys(Json& o, V3 d);

void editCsgNode(Json& n, V3 d) {
  if (hasTransform(n)) {
    editTranslate(n, d);
  } else if (n.contains("op")) {
    for (Json& c : n["children"]) editCsgNode(c, d);
  } else {
    editShapeKeys(n, d);
  }
}

void editShapeKeys(Json& o, V3 d) {
  const std::string type = o.value("type", "");
  const Similarity x = translation(d);
  if (type == "sphere") {
    if (!o.contains("center")) o["center"] = Json::array({0, 0, 0});
    movePoint(o, "center", x);
  } else if (type == "box") {
    movePoint(o, "min", x);
    movePoint(o, "max", x);
  } else if (type == "plane") {
    if (!o.contains("point")) o["point"] = Json::array({0, 0, 0});
    movePoint(o, "point", x);
  } else if (type == "quad") {
    movePoint(o, "corner", x);
  } else if (type == "csg" && o.contains("tree")) {
    editCsgNode(o["tree"], d);
  } else {  // cylinder, cone, disk, terrain, a .csg file: no position key
    editTranslate(o, d);
  }
}

// Returns true when the object was moved by its shape keys (its object space stayed put).
bool moveObject(Json& obj, Context& c) {
  const Similarity& x = c.x;
  if (obj.contains("animation")) {
    moveAnimation(obj["animation"], x);
    appendOp(obj, x.linearOp);
    return false;
  }
  if (c.mode == Placement::Root) {
    appendOp(obj, x.op);
    return false;
  }
  if (hasTransform(obj)) {
    editTranslate(obj, x.t);
    return false;
  }
  if (nodeReadsObjectSpace(c.scene, obj)) {
    // Its shape keys are object-space coordinates: moving them would move the object through
    // its own texture (or snow) pattern, which is not the same scene. It moves by a transform.
    editTranslate(obj, x.t);
    c.note(
        "edit: objects whose material is keyed to object space (procedural textures, snow) "
        "move by a transform, not by their shape keys");
    return false;
  }
  editShapeKeys(obj, x.t);
  return true;
}

void moveCamera(Json& cam, Context& c) {
  const std::string name = cam.value("name", "");
  const bool animated = cam.contains("animation");
  const Similarity x = animated ? linearPart(c.x) : c.x;
  if (animated) moveAnimation(cam["animation"], c.x);
  if (cam.contains("transform")) {
    if (c.mode == Placement::Edit && !animated)
      editTranslate(cam, x.t);
    else
      appendOp(cam, x.op);
    return;  // lens, clipping and magnification are in camera space, which scales with it
  }
  if (x.handedness() < 0) {
    // position/look_at/up always make a right-handed frame, which would mirror the image:
    // the mirrored camera is written as the matrix x . (its frame at the scene time).
    if (animated) throw std::runtime_error("camera '" + name + "': animated, cannot be mirrored");
    const auto& f = c.facts.cameraFrames.at(name);
    Json rows = Json::array();
    for (int i = 0; i < 3; ++i) {
      Json row = Json::array();
      for (int j = 0; j < 4; ++j) {
        double v = 0;
        for (int k = 0; k < 3; ++k) v += x.R[size_t(i)][size_t(k)] * x.s * f[size_t(k)][size_t(j)];
        if (j == 3) v += i == 0 ? x.t.x : i == 1 ? x.t.y : x.t.z;
        row.push_back(v);
      }
      rows.push_back(row);
    }
    rows.push_back(Json::array({0, 0, 0, 1}));
    cam.erase("position"), cam.erase("look_at"), cam.erase("up");
    cam["transform"] = Json::array({Json{{"matrix", rows}}});
    if (!cam.contains("focus_distance") && c.facts.focusDistances.count(name) &&
        c.facts.focusDistances.at(name) > 0)
      cam["focus_distance"] = c.facts.focusDistances.at(name);
    c.note("mirror: cameras become transform matrices (position/look_at frames are right-handed)");
    return;
  }
  if (x.turns() && !cam.contains("up")) cam["up"] = Json::array({0, 1, 0});  // the default
  movePoint(cam, "position", x);
  movePoint(cam, "look_at", x);
  turnDirection(cam, "up", x);
  if (x.s != 1) {
    for (const char* key : {"aperture", "focus_distance", "znear", "xmag", "ymag"})
      multiply(cam, key, x.s);
    if (cam.contains("zfar")) multiply(cam, "zfar", x.s);
    c.note("scale: camera aperture, focus distance, znear/zfar, xmag/ymag times s");
  }
}

void moveLight(Json& l, Context& c) {
  const std::string type = l.value("type", "");
  const bool animated = l.contains("animation");
  const Similarity x = animated ? linearPart(c.x) : c.x;
  if (animated) moveAnimation(l["animation"], c.x);
  if (l.contains("transform")) {
    if (c.mode == Placement::Edit && !animated)
      editTranslate(l, x.t);
    else
      appendOp(l, x.op);
  } else {
    if (type == "projective" && x.turns() && !l.contains("up")) {
      // The slide's +Y: glint's default (scenes/sidecar_lights.cpp), made explicit to turn it.
      const V3 d = normalized(l.contains("direction") ? toV3(l["direction"])
                                                      : toV3(l["look_at"]) - toV3(l["position"]));
      l["up"] = std::abs(d.y) > 0.9 ? Json::array({1, 0, 0}) : Json::array({0, 1, 0});
    }
    movePoint(l, "position", x);
    movePoint(l, "look_at", x);
    turnDirection(l, "direction", x);
    turnDirection(l, "up", x);
    movePoint(l, "corner", x);
    moveVector(l, "edge_u", x);
    moveVector(l, "edge_v", x);
    multiply(l, "radius", x.s);
    if (type == "quad" && x.handedness() < 0) {
      // A quad emits towards edge_u x edge_v; mirrored edges would turn it to the other side.
      std::swap(l["edge_u"], l["edge_v"]);
      c.note("mirror: a quad light's edges swapped (it emits towards edge_u x edge_v)");
    }
  }
  if (x.s != 1 && (type == "point" || type == "spot" || type == "projective")) {
    multiply(l, "intensity", x.s * x.s);
    c.note(
        "scale: point, spot and projective intensities times s^2 (candela; area lights emit "
        "radiance and directional lights irradiance, which do not change)");
  }
  multiply(l, "range", x.s);
  if (type == "projective" && c.x.handedness() < 0) {
    // The slide's frame is right-handed (X = up x -direction): mirrored, the slide would be
    // the mirror image of itself. With attenuation 0 the projector is a plain square frustum
    // light, which a mirror maps to itself; the caller switches the slide off in both scenes.
    if (l.value("attenuation", Json(1.0)) != Json(0) &&
        l.value("attenuation", Json(1.0)) != Json(0.0))
      throw std::runtime_error(
          "a projective light's slide cannot be mirrored (attenuation must be 0)");
  }
}

void moveTexture(Json& tex, Context& c) {
  if (!tex.contains("mapping") || tex["mapping"].value("space", "") != "world") return;
  Json& m = tex["mapping"];
  const Similarity& x = c.x;
  if (x.turns())
    throw std::runtime_error("texture '" + tex.value("name", "") +
                             "' is mapped in world space, which has no rotation");
  // map3D = p * scale + offset; p' = s p + t: scale' = scale / s, offset' = offset - t * scale / s.
  V3 scale{1, 1, 1};
  if (m.contains("scale"))
    scale = m["scale"].is_number() ? V3{1, 1, 1} * m["scale"].get<double>() : toV3(m["scale"]);
  if (x.moves()) {
    if (!m.contains("offset")) m["offset"] = Json::array({0, 0, 0});
    mapKeyed(m["offset"], [&](Json& v) {
      const V3 o = toV3(v);
      v = toJson(
          {o.x - x.t.x * scale.x / x.s, o.y - x.t.y * scale.y / x.s, o.z - x.t.z * scale.z / x.s});
    });
    c.note(
        "translate: world-space texture mappings get the offset that keeps the pattern in place");
  }
  if (x.s != 1) {
    if (!m.contains("scale")) m["scale"] = 1.0;
    multiply(m, "scale", 1 / x.s);
    c.note("scale: world-space texture mappings' scale divided by s");
  }
}

void moveMaterial(Json& mat, Context& c) {
  if (c.x.s == 1) return;
  if (mat.contains("bump")) {
    multiply(mat["bump"], "strength", c.x.s);
    c.note("scale: bump strength (a displacement in world units) times s");
  }
  if (mat.contains("volume")) {
    multiply(mat["volume"], "attenuation_distance", c.x.s);
    c.note("scale: volume attenuation distance times s");
  }
}

// A medium's noise density keyed to a region that moved through its own object space.
void shiftNoise(Json& medium, V3 d, Context& c) {
  if (!medium.contains("density") || medium["density"].value("type", "") != "noise") return;
  Json& den = medium["density"];
  if (!den.contains("offset")) den["offset"] = Json::array({0, 0, 0});
  mapKeyed(den["offset"], [&](Json& v) { v = toJson(toV3(v) + d); });
  c.note("edit: noise densities of media moved by their region's keys get the same offset");
}

void moveMedium(Json& m, Context& c) {
  const Similarity& x = c.x;
  for (const char* key : {"sigma_a", "sigma_s", "emission"}) multiply(m, key, 1 / x.s);
  if (x.s != 1) c.note("scale: media coefficients (per unit length) divided by s");
  Json* density = m.contains("density") ? &m["density"] : nullptr;
  const std::string dtype = density ? density->value("type", "constant") : "constant";
  if (m.contains("region")) {
    Json& region = m["region"];
    if (c.mode == Placement::Root) {
      appendOp(region, x.op);
    } else if (hasTransform(region)) {
      editTranslate(region, x.t);
    } else {
      editShapeKeys(region, x.t);
      shiftNoise(m, x.t, c);
    }
    return;
  }
  if (m.contains("object")) {
    if (c.shapeEdited.count(m["object"].get<std::string>())) shiftNoise(m, x.t, c);
    return;
  }
  if (dtype == "vdb") {
    // Placed as objects are, by its transform (or animation) over the file's own space. Its
    // emission is per unit length, as the coefficients: the same factor.
    if (m.contains("animation")) {
      moveAnimation(m["animation"], x);
      appendOp(m, x.linearOp);
    } else if (c.mode == Placement::Root) {
      appendOp(m, x.op);
    } else {
      editTranslate(m, x.t);
    }
    if (x.s != 1) {
      if (density->contains("temperature_grid"))
        (*density)["blackbody_intensity"] = density->value("blackbody_intensity", 1.0) / x.s;
      if (density->contains("flame_grid"))
        (*density)["flame_strength"] = density->value("flame_strength", 1.0) / x.s;
      c.note("scale: a VDB medium's blackbody intensity and flame strength divided by s");
    }
    return;
  }
  // The whole scene: the field is in world space.
  if (dtype == "noise") {
    if (x.turns()) throw std::runtime_error("a whole-scene noise density has no rotation");
    // n(scale (p - offset)); p' = s p + t: scale' = scale / s, offset' = s offset + t.
    multiply(*density, "scale", 1 / x.s);
    if (!density->contains("offset")) (*density)["offset"] = Json::array({0, 0, 0});
    mapKeyed((*density)["offset"], [&](Json& v) { v = toJson(toV3(v) * x.s + x.t); });
  } else if (dtype == "exponential") {
    // exp(-falloff (p . up - height)), up normalised.
    const V3 up = normalized(density->contains("up") ? toV3((*density)["up"]) : V3{0, 1, 0});
    const V3 upTurned = x.rotate(up);
    if (x.turns()) (*density)["up"] = toJson(upTurned);
    multiply(*density, "falloff", 1 / x.s);
    const double h = density->value("height", 0.0);
    (*density)["height"] = h * x.s + dot(x.t, upTurned);
    c.note("whole-scene exponential density: height, falloff and up follow the map");
  } else if (dtype == "grid") {
    if (x.turns()) throw std::runtime_error("a whole-scene grid density spans the world box");
  }
}

}  // namespace

Json transformScene(const Json& scene, const Similarity& x, Placement mode, const SceneFacts& facts,
                    std::vector<std::string>* notes) {
  if (mode == Placement::Edit && (x.turns() || x.s != 1))
    throw std::runtime_error("edit mode is for translations");
  Context c{x, mode, facts, notes, scene, {}};
  Json out = scene;
  for (const auto& [key, value] : out.items()) {
    static const std::set<std::string> known = {"render",    "gltf",        "cameras",
                                                "lights",    "environment", "textures",
                                                "materials", "objects",     "media"};
    if (!known.count(key)) throw std::runtime_error("unknown top-level key '" + key + "'");
  }
  if (out.contains("gltf")) {
    for (Json& e : out["gltf"]) {
      if (e.is_string()) e = {{"file", e}};
      if (mode == Placement::Edit)
        editTranslate(e, x.t);
      else
        appendOp(e, x.op);
    }
  }
  if (out.contains("cameras"))
    for (Json& cam : out["cameras"]) moveCamera(cam, c);
  if (out.contains("lights"))
    for (Json& l : out["lights"]) moveLight(l, c);
  if (out.contains("environment")) {
    Json& env = out["environment"];
    if (x.turns() && !env.contains("color")) {
      // An image or the studio turns only about +Y: only such a rotation can be written.
      const V3 y = x.rotate({0, 1, 0});
      if (x.handedness() < 0 || std::abs(y.y - 1) > 1e-12)
        throw std::runtime_error("the environment map turns only about +Y");
      const double degrees = std::atan2(x.R[0][2], x.R[0][0]) * 180 / std::numbers::pi;
      env["rotation_degrees"] = env.value("rotation_degrees", 0.0) + degrees;
      c.note("rotate about +Y: the environment's rotation_degrees turned with the scene");
    }
  } else if (x.turns() && !out.contains("lights") && facts.gltfPunctualLights == 0) {
    throw std::runtime_error("the default studio light turns only about +Y (make it explicit)");
  }
  if (out.contains("textures"))
    for (Json& t : out["textures"]) moveTexture(t, c);
  if (out.contains("materials"))
    for (Json& m : out["materials"]) moveMaterial(m, c);
  // glTF materials' volumes, after the scene's own materials (which moveMaterial scaled).
  if (x.s != 1 && out.contains("gltf")) {
    for (const auto& [name, volume] : facts.gltfVolumes) {
      if (!volume.contains("attenuationDistance")) continue;  // infinite: nothing to scale
      Json v = {{"thickness", volume.value("thicknessFactor", 0.0)},
                {"attenuation_distance", volume.value("attenuationDistance", 0.0) * x.s}};
      if (volume.contains("attenuationColor")) v["attenuation_color"] = volume["attenuationColor"];
      if (!out.contains("materials")) out["materials"] = Json::array();
      Json* existing = nullptr;
      for (Json& m : out["materials"])
        if (m.value("name", "") == name) existing = &m;
      if (existing && existing->contains("volume")) continue;  // the scene's own, scaled above
      if (existing)
        (*existing)["volume"] = v;
      else
        out["materials"].push_back({{"name", name}, {"volume", v}});
    }
    if (!facts.gltfVolumes.empty())
      c.note("scale: glTF volume attenuation distances times s (a material override)");
    if (facts.gltfPunctualLights > 0)
      throw std::runtime_error("glTF punctual lights cannot be rescaled from the scene file");
  }
  if (out.contains("objects"))
    for (Json& o : out["objects"])
      if (moveObject(o, c) && o.contains("name"))
        c.shapeEdited.insert(o["name"].get<std::string>());
  if (out.contains("media"))
    for (Json& m : out["media"]) moveMedium(m, c);
  if (out.contains("render") && out["render"].contains("integrator") &&
      out["render"]["integrator"].is_object() && x.s != 1) {
    Json& integ = out["render"]["integrator"];
    if (integ.contains("volume_step")) {
      multiply(integ, "volume_step", x.s);
      c.note("scale: the volume march step times s");
    }
    if (integ.contains("vpl_clamp")) {
      multiply(integ, "vpl_clamp", 1 / (x.s * x.s));
      c.note("scale: instant radiosity's vpl_clamp (a bound in 1/length^2) divided by s^2");
    }
  }
  return out;
}

std::vector<std::string> rotationBlockers(const Json& scene) {
  std::vector<std::string> why;
  if (scene.contains("textures"))
    for (const Json& t : scene["textures"])
      if (t.contains("mapping") && t["mapping"].value("space", "") == "world")
        why.push_back("texture '" + t.value("name", "") +
                      "' is mapped in world space, which has no rotation key");
  if (scene.contains("environment") && !scene["environment"].contains("color"))
    why.push_back("the environment map (or studio) turns only about +Y");
  if (!scene.contains("environment") && !scene.contains("lights"))
    why.push_back("the default studio light turns only about +Y");
  if (scene.contains("media"))
    for (const Json& m : scene["media"])
      if (!m.contains("region") && !m.contains("object") && m.contains("density")) {
        const std::string type = m["density"].value("type", "constant");
        if (type == "noise" || type == "grid")
          why.push_back("medium '" + m.value("name", "") + "' has a " + type +
                        " density in world space, which has no rotation key");
      }
  return why;
}

SceneFacts sceneFacts(const Json& scene, const std::string& file) {
  SceneFacts f;
  SceneDescription d;
  d.file = file;
  applySceneJson(scene, file, SceneJsonKind::Scene, &d);
  for (const CameraDesc& cam : d.cameras) {
    std::array<std::array<double, 4>, 4> m{};
    const Mat4& w = cam.worldFromCamera.matrix();
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) m[size_t(i)][size_t(j)] = w.m[size_t(i)][size_t(j)];
    f.cameraFrames[cam.name] = m;
    f.focusDistances[cam.name] = cam.focusDistance;
  }
  const size_t own = scene.contains("lights") ? scene["lights"].size() : 0;
  f.gltfPunctualLights = int(d.lights.size() - std::min(own, d.lights.size()));
  return f;
}

// ---------------------------------------------------------------------------------------------
// Rendering and comparison
// ---------------------------------------------------------------------------------------------

Film renderScene(const Json& scene, const std::string& file, SceneFeatures* features) {
  SceneDescription d;
  d.file = file;
  applySceneJson(scene, file, SceneJsonKind::Scene, &d);
  RenderScene built = buildRenderScene(d);
  if (features) *features = built.features();
  auto integrator = makeIntegrator(built, d.render);
  RenderStats stats;
  return render(built, *integrator, d.render, {.threads = 2}, &stats);
}

namespace {
double luminanceOf(Rgb c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
double channel(Rgb c, int k) { return k == 0 ? c.x : k == 1 ? c.y : c.z; }
}  // namespace

std::string Comparison::summary() const {
  char text[640];
  std::snprintf(text, sizeof text,
                "%d bad %s of %d x %d (worst at (%d, %d): %.4g vs %.4g, %.3f outside the "
                "allowed range); largest difference anywhere %.4g at (%d, %d) (%.4g vs %.4g); "
                "mean luminance %.5g vs %.5g (%+.3f%%)%s",
                bad, block > 1 ? "blocks" : "pixels", width, height, worstX, worstY, worstA, worstB,
                worstExcess, maxDiff, maxDiffX, maxDiffY, maxDiffA, maxDiffB, meanA, meanB,
                100 * (meanB - meanA) / meanA, nonFinite ? "; NON-FINITE PIXELS" : "");
  return text;
}

namespace {
// `film` averaged over block x block pixels (the variance of the block mean: the pixels' own
// variances over block^4, as if independent).
Film blockAverage(const Film& film, int block) {
  if (block <= 1) return film;
  Film out((film.width + block - 1) / block, (film.height + block - 1) / block, false);
  std::vector<int> count(out.color.size(), 0);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      const size_t o = out.index(x / block, y / block), i = film.index(x, y);
      out.color[o] = out.color[o] + film.color[i];
      if (!film.variance.empty()) out.variance[o] = out.variance[o] + film.variance[i];
      ++count[o];
    }
  for (size_t o = 0; o < out.color.size(); ++o) {
    out.color[o] = out.color[o] / float(count[o]);
    out.variance[o] = out.variance[o] / float(count[o] * count[o]);
  }
  return out;
}

double varianceOf(const Film& f, size_t i, int k) {
  return f.variance.empty() ? 0.0 : std::max(0.0, channel(f.variance[i], k));
}
}  // namespace

Comparison compareFilms(const Film& fullA, const Film& fullB, const Tolerance& tol,
                        const std::vector<const Film*>& alternates) {
  Comparison r;
  if (fullA.width != fullB.width || fullA.height != fullB.height)
    throw std::runtime_error("films of different sizes");
  const Film a = blockAverage(fullA, tol.block), b = blockAverage(fullB, tol.block);
  const int w = a.width, h = a.height;
  r.width = fullA.width, r.height = fullA.height, r.block = std::max(1, tol.block);
  r.badMask.assign(size_t(r.width) * size_t(r.height), 0);
  double sumA = 0, sumB = 0, varSum = 0;
  for (size_t i = 0; i < fullA.color.size(); ++i) {
    sumA += luminanceOf(fullA.color[i]);
    sumB += luminanceOf(fullB.color[i]);
    const double wts[3] = {0.2126, 0.7152, 0.0722};
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(channel(fullA.color[i], k)) || !std::isfinite(channel(fullB.color[i], k)))
        r.nonFinite = true;
      varSum += wts[k] * wts[k] * (varianceOf(fullA, i, k) + varianceOf(fullB, i, k));
    }
  }
  const double n = double(fullA.color.size());
  r.meanA = sumA / n;
  r.meanB = sumB / n;
  r.relMean = r.meanA > 0 ? std::abs(r.meanB - r.meanA) / r.meanA : std::abs(r.meanB);
  if (tol.meanSigmas > 0 && r.meanA > 0)
    r.meanNoise = tol.meanSigmas * std::sqrt(varSum) / n / r.meanA;
  const double key = 2 * std::max(r.meanA, 1e-6);
  auto squeeze = [&](double x) {
    const double y = std::max(0.0, x) / key;
    return y / (1 + y);
  };
  // Squeezed channels of both images, and each pixel's allowance for independent noise.
  std::vector<double> va(size_t(w) * size_t(h) * 3), vb(va.size()), noise(va.size(), 0.0);
  for (size_t i = 0; i < a.color.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double xa = channel(a.color[i], k), xb = channel(b.color[i], k);
      va[3 * i + size_t(k)] = squeeze(xa);
      vb[3 * i + size_t(k)] = squeeze(xb);
      if (tol.sigmas > 0) {
        const double y = std::max(0.0, 0.5 * (xa + xb)) / key;
        const double slope = 1 / (key * (1 + y) * (1 + y));  // dv/dx
        noise[3 * i + size_t(k)] =
            tol.sigmas * slope * std::sqrt(varianceOf(a, i, k) + varianceOf(b, i, k));
      }
    }
  if (!alternates.empty() && tol.meanSigmas > 0 && r.meanA > 0) {
    double sq = 0;
    for (const Film* alt : alternates) {
      double sumAlt = 0;
      for (const Rgb& c : alt->color) sumAlt += luminanceOf(c);
      sq += (sumAlt / n - r.meanA) * (sumAlt / n - r.meanA);
    }
    r.meanNoise += tol.meanSigmas * std::sqrt(sq / double(alternates.size())) / r.meanA;
  }
  if (!alternates.empty()) {
    // The seed-to-seed differences' root mean square over each window.
    std::vector<double> d2(va.size(), 0.0);
    for (const Film* alternate : alternates) {
      const Film alt = blockAverage(*alternate, tol.block);
      for (size_t i = 0; i < alt.color.size(); ++i)
        for (int k = 0; k < 3; ++k) {
          const double d = squeeze(channel(alt.color[i], k)) - va[3 * i + size_t(k)];
          d2[3 * i + size_t(k)] += d * d / double(alternates.size());
        }
    }
    const int rad = std::max(1, tol.radius);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < 3; ++k) {
          double sum = 0;
          int count = 0;
          for (int dy = -rad; dy <= rad; ++dy)
            for (int dx = -rad; dx <= rad; ++dx) {
              const int nx = x + dx, ny = y + dy;
              if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
              sum += d2[(size_t(ny) * size_t(w) + size_t(nx)) * 3 + size_t(k)];
              ++count;
            }
          noise[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(k)] +=
              tol.altSigmas * std::sqrt(sum / count);
        }
  }
  // Window minima and maxima (separable: rows, then columns).
  auto windowed = [&](const std::vector<double>& v, bool takeMax) {
    std::vector<double> rows(v.size()), out(v.size());
    const int rad = tol.radius;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < 3; ++k) {
          double m = takeMax ? -1e300 : 1e300;
          for (int dx = -rad; dx <= rad; ++dx) {
            const int nx = std::clamp(x + dx, 0, w - 1);
            const double s = v[(size_t(y) * size_t(w) + size_t(nx)) * 3 + size_t(k)];
            m = takeMax ? std::max(m, s) : std::min(m, s);
          }
          rows[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(k)] = m;
        }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < 3; ++k) {
          double m = takeMax ? -1e300 : 1e300;
          for (int dy = -rad; dy <= rad; ++dy) {
            const int ny = std::clamp(y + dy, 0, h - 1);
            const double s = rows[(size_t(ny) * size_t(w) + size_t(x)) * 3 + size_t(k)];
            m = takeMax ? std::max(m, s) : std::min(m, s);
          }
          out[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(k)] = m;
        }
    return out;
  };
  const std::vector<double> loA = windowed(va, false), hiA = windowed(va, true);
  const std::vector<double> loB = windowed(vb, false), hiB = windowed(vb, true);
  // The largest difference anywhere, at full resolution (reported, not judged).
  for (int y = 0; y < fullA.height; ++y)
    for (int x = 0; x < fullA.width; ++x)
      for (int k = 0; k < 3; ++k) {
        const size_t p = fullA.index(x, y);
        const double d = std::abs(channel(fullA.color[p], k) - channel(fullB.color[p], k));
        if (d > r.maxDiff) {
          r.maxDiff = d, r.maxDiffX = x, r.maxDiffY = y;
          r.maxDiffA = channel(fullA.color[p], k), r.maxDiffB = channel(fullB.color[p], k);
        }
      }
  const int B = std::max(1, tol.block);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * size_t(w) + size_t(x);
      double excess = 0;
      int worstK = 0;
      for (int k = 0; k < 3; ++k) {
        const size_t i = 3 * p + size_t(k);
        const double e =
            std::max({loA[i] - vb[i], vb[i] - hiA[i], loB[i] - va[i], va[i] - hiB[i]}) - noise[i];
        if (e > excess) excess = e, worstK = k;
      }
      r.largestExcess = std::max(r.largestExcess, excess);
      if (excess <= tol.pixel) continue;
      // A pixel (or a block's pixels) of the full image.
      for (int yy = y * B; yy < std::min(fullA.height, (y + 1) * B); ++yy)
        for (int xx = x * B; xx < std::min(fullA.width, (x + 1) * B); ++xx)
          r.badMask[fullA.index(xx, yy)] = 1;
      ++r.bad;
      const int fx = x * B + B / 2, fy = y * B + B / 2;  // where, in full-image pixels
      if (excess - tol.pixel > r.worstExcess || r.worstX < 0) {
        r.worstExcess = excess - tol.pixel;
        r.worstX = std::min(fx, fullA.width - 1), r.worstY = std::min(fy, fullA.height - 1);
        r.worstA = channel(a.color[p], worstK), r.worstB = channel(b.color[p], worstK);
      }
      if (r.bad <= 5) {
        char text[96];
        std::snprintf(text, sizeof text, " (%d, %d) %.4g vs %.4g", std::min(fx, fullA.width - 1),
                      std::min(fy, fullA.height - 1), channel(a.color[p], worstK),
                      channel(b.color[p], worstK));
        r.where += text;
      }
    }
  return r;
}

void writeFilm(const std::string& pathStem, const Film& film) {
  RenderSettings settings;
  ImageMetadata meta;
  writeImage(pathStem + ".exr", film, settings, meta);
  try {
    writeImage(pathStem + ".png", film, settings, meta);
  } catch (const std::exception&) {
    // the PNG needs the OpenImageIO plugin; the EXR is what counts
  }
}

void writeMask(const std::string& path, const Film& film, const std::vector<uint8_t>& mask) {
  std::vector<float> pixels(size_t(film.width) * size_t(film.height) * 3);
  double mean = 0;
  for (const Rgb& c : film.color) mean += luminanceOf(c);
  mean = std::max(mean / double(film.color.size()), 1e-6);
  for (size_t i = 0; i < film.color.size(); ++i) {
    const double y = luminanceOf(film.color[i]) / (2 * mean);
    const float grey = float(0.4 * y / (1 + y));
    pixels[3 * i] = mask[i] ? 1.0f : grey;
    pixels[3 * i + 1] = mask[i] ? 0.0f : grey;
    pixels[3 * i + 2] = mask[i] ? 0.0f : grey;
  }
  try {
    writeRawImage(path, film.width, film.height, 3, pixels);
  } catch (const std::exception&) {
  }
}

}  // namespace glint::invariance
