// glint — glTF animations: samplers (keyframe accessors, interpolation) and channels (target
// node and path), with the accessor layouts each path needs checked here; the keyframe data
// itself is checked by the loader, which decodes it.
#include <string>

#include "scenes/gltf_document_parts.h"

namespace glint::gltf {

namespace {

const char* pathName(AnimationPath path) {
  switch (path) {
    case AnimationPath::Translation:
      return "translation";
    case AnimationPath::Rotation:
      return "rotation";
    case AnimationPath::Scale:
      return "scale";
    case AnimationPath::Weights:
      return "weights";
  }
  return "translation";
}

bool isNormalizedInteger(const Accessor& a) {
  return a.normalized && a.componentType != kFloat && a.componentType != kUnsignedInt;
}

// The output accessor of `sampler` must suit `channel`'s path (glTF 2.0, "Animations"):
// translation and scale VEC3 of FLOAT, rotation VEC4 of FLOAT or normalized (UNSIGNED_)BYTE /
// (UNSIGNED_)SHORT, with one element per key (three for CUBICSPLINE: in-tangent, value,
// out-tangent).
void checkOutput(const Document& doc, const Animation& anim, const AnimationChannel& channel) {
  const AnimationSampler& sampler = anim.samplers[size_t(channel.sampler)];
  const Accessor& out = doc.accessors[size_t(sampler.output)];
  const Accessor& in = doc.accessors[size_t(sampler.input)];
  SourceLocation loc = sampler.where.child("output");
  std::string user =
      "the '" + std::string(pathName(channel.path)) + "' channel at " + channel.where.pointer;
  bool ok = true;
  std::string want;
  switch (channel.path) {
    case AnimationPath::Translation:
    case AnimationPath::Scale:
      ok = out.type == "VEC3" && out.componentType == kFloat;
      want = "VEC3 of FLOAT";
      break;
    case AnimationPath::Rotation:
      ok = out.type == "VEC4" && (out.componentType == kFloat || isNormalizedInteger(out));
      want = "VEC4 of FLOAT or of normalized BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
      break;
    case AnimationPath::Weights:
      ok = out.type == "SCALAR" && (out.componentType == kFloat || isNormalizedInteger(out));
      want = "SCALAR of FLOAT or of a normalized integer type";
      break;
  }
  if (!ok)
    throw SceneError(loc, "accessor " + std::to_string(sampler.output) + " is " + out.type +
                              " of " + (out.normalized ? "normalized " : "") +
                              componentTypeName(out.componentType) + "; " + user + " needs " +
                              want);
  size_t perKey = sampler.interpolation == Interpolation::CubicSpline ? 3 : 1;
  if (channel.path == AnimationPath::Weights) {  // one value per morph target and key
    if (channel.node < 0) return;
    const Node& node = doc.nodes[size_t(channel.node)];
    const size_t targets = node.mesh >= 0 ? doc.meshes[size_t(node.mesh)].targetCount : 0;
    if (targets == 0) return;  // nothing to drive: the loader warns and ignores it
    perKey *= targets;
    if (out.count != perKey * in.count)
      throw SceneError(
          loc, "accessor " + std::to_string(sampler.output) + " has " +
                   plural(out.count, "element") + "; " + user + " with " + plural(in.count, "key") +
                   " and " + plural(targets, "morph target") +
                   (sampler.interpolation == Interpolation::CubicSpline ? " (CUBICSPLINE)" : "") +
                   " needs " + std::to_string(perKey * in.count));
    return;
  }
  if (out.count != perKey * in.count)
    throw SceneError(loc, "accessor " + std::to_string(sampler.output) + " has " +
                              plural(out.count, "element") + "; " + user + " with " +
                              plural(in.count, "key") + (perKey == 3 ? " (CUBICSPLINE)" : "") +
                              " needs " + std::to_string(perKey * in.count));
}

}  // namespace

void readAnimations(JsonReader& root, Document* doc) {
  size_t index = 0;
  for (const JsonItem& item : root.optionalArray("animations")) {
    JsonReader o(item);
    Animation anim;
    anim.where = o.where();
    anim.name = o.get<std::string>("name", "animation " + std::to_string(index++));
    o.require("samplers");
    for (JsonReader* so : o.objects("samplers")) {
      AnimationSampler s;
      s.where = so->where();
      s.input = so->index("input", doc->accessors.size(), "accessor");
      s.output = so->index("output", doc->accessors.size(), "accessor");
      std::string interpolation = so->get<std::string>("interpolation", "LINEAR");
      if (interpolation == "LINEAR")
        s.interpolation = Interpolation::Linear;
      else if (interpolation == "STEP")
        s.interpolation = Interpolation::Step;
      else if (interpolation == "CUBICSPLINE")
        s.interpolation = Interpolation::CubicSpline;
      else
        throw SceneError(
            so->where("interpolation"),
            "unknown interpolation '" + interpolation + "' (expected LINEAR, STEP or CUBICSPLINE)");
      const Accessor& in = doc->accessors[size_t(s.input)];
      if (in.type != "SCALAR" || in.componentType != kFloat)
        throw SceneError(so->where("input"), "accessor " + std::to_string(s.input) + " is " +
                                                 in.type + " of " +
                                                 componentTypeName(in.componentType) +
                                                 "; keyframe times must be SCALAR of FLOAT");
      if (s.interpolation == Interpolation::CubicSpline && in.count < 2)
        throw SceneError(so->where("input"), "CUBICSPLINE needs at least 2 keys");
      anim.samplers.push_back(s);
    }
    if (anim.samplers.empty()) throw SceneError(o.where("samplers"), "must not be empty");
    o.require("channels");
    for (JsonReader* co : o.objects("channels")) {
      AnimationChannel c;
      c.where = co->where();
      c.sampler = co->index("sampler", anim.samplers.size(), "sampler");
      JsonReader& target = co->object("target");
      c.node = target.index("node", doc->nodes.size(), "node", -1);
      std::string path = target.get<std::string>("path");
      if (path == "translation")
        c.path = AnimationPath::Translation;
      else if (path == "rotation")
        c.path = AnimationPath::Rotation;
      else if (path == "scale")
        c.path = AnimationPath::Scale;
      else if (path == "weights")
        c.path = AnimationPath::Weights;
      else
        throw SceneError(
            target.where("path"),
            "unknown path '" + path + "' (expected translation, rotation, scale or weights)");
      if (c.node >= 0 && c.path != AnimationPath::Weights && doc->nodes[size_t(c.node)].hasMatrix)
        throw SceneError(target.where("node"), "node " + std::to_string(c.node) +
                                                   " has a matrix; only nodes given by "
                                                   "translation/rotation/scale may be animated");
      for (const AnimationChannel& other : anim.channels)
        if (c.node >= 0 && other.node == c.node && other.path == c.path)
          throw SceneError(co->where(), "node " + std::to_string(c.node) + " '" + path +
                                            "' is already animated by " + other.where.pointer);
      checkOutput(*doc, anim, c);
      anim.channels.push_back(c);
    }
    if (anim.channels.empty()) throw SceneError(o.where("channels"), "must not be empty");
    doc->animations.push_back(anim);
  }
}

}  // namespace glint::gltf
