// glint — glTF animations into keyframe tracks (see gltf_animation.h).
#include "scenes/gltf_animation.h"

#include <cmath>
#include <type_traits>

#include "scenes/errors.h"

namespace glint::gltf {

namespace {

// Keyframe times of sampler `s`: finite, >= 0 and strictly increasing (glTF 2.0).
std::vector<float> readTimes(const AnimationSampler& s, const AccessorReader& reader) {
  std::vector<double> v = reader.read(s.input);
  std::vector<float> times(v.size());
  SourceLocation at = s.where.child("input");
  for (size_t i = 0; i < v.size(); ++i) {
    times[i] = float(v[i]);
    if (!std::isfinite(times[i]) || times[i] < 0)
      throw SceneError(at, "accessor " + std::to_string(s.input) + ": key " + std::to_string(i) +
                               " has time " + std::to_string(v[i]) +
                               "; times must be finite and >= 0");
    if (i > 0 && !(times[i] > times[i - 1]))
      throw SceneError(at, "accessor " + std::to_string(s.input) + ": key " + std::to_string(i) +
                               " at time " + std::to_string(times[i]) +
                               " does not come after key " + std::to_string(i - 1) + " at " +
                               std::to_string(times[i - 1]) + "; times must increase strictly");
  }
  return times;
}

template <class T>
void fillTrack(Track<T>* track, const AnimationSampler& s, const AnimationChannel& c,
               const Document& doc, const AccessorReader& reader) {
  const AnimationPath path = c.path;
  track->interpolation = s.interpolation;
  track->times = readTimes(s, reader);
  track->where = c.where;
  std::vector<double> v = reader.read(s.output);
  const Accessor& out = doc.accessors[size_t(s.output)];
  size_t n = out.count;
  bool cubic = s.interpolation == Interpolation::CubicSpline;
  SourceLocation at = s.where.child("output");
  for (size_t i = 0; i < n; ++i) {
    // Only key values (not CUBICSPLINE tangents) must be unit quaternions and non-zero scales.
    bool isValue = !cubic || i % 3 == 1;
    std::string which = "element " + std::to_string(i) + " of accessor " + std::to_string(s.output);
    if constexpr (std::is_same_v<T, Quaternion>) {
      Quaternion q{float(v[4 * i]), float(v[4 * i + 1]), float(v[4 * i + 2]), float(v[4 * i + 3])};
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) || !std::isfinite(q.w))
        throw SceneError(at, which + " is not finite");
      if (isValue) {
        if (!(dot(q, q) > 1e-12f)) throw SceneError(at, which + " is a zero quaternion");
        q = normalize(q);
      }
      track->values.push_back(q);
    } else {
      Vec3f x{float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
      if (!isFinite(x)) throw SceneError(at, which + " is not finite");
      if (isValue && path == AnimationPath::Scale && (x.x == 0 || x.y == 0 || x.z == 0))
        throw SceneError(at, which +
                                 " is a scale with a zero component, which glint cannot "
                                 "place (the node matrix would not be invertible)");
      track->values.push_back(x);
    }
  }
}

// A weights channel as one track per morph target: glTF interleaves the targets within each
// key (and, for CUBICSPLINE, in-tangents, values, out-tangents each as a run of targets).
std::vector<Track<float>> readWeightTracks(const AnimationSampler& s, const AnimationChannel& c,
                                           const Document& doc, const AccessorReader& reader) {
  const size_t targets = doc.meshes[size_t(doc.nodes[size_t(c.node)].mesh)].targetCount;
  std::vector<Track<float>> tracks(targets);
  const std::vector<float> times = readTimes(s, reader);
  const std::vector<double> v = reader.read(s.output);
  const bool cubic = s.interpolation == Interpolation::CubicSpline;
  const size_t perKey = cubic ? 3 : 1;
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw SceneError(s.where.child("output"), "element " + std::to_string(i) + " of accessor " +
                                                    std::to_string(s.output) + " is not finite");
  for (size_t t = 0; t < targets; ++t) {
    tracks[t].interpolation = s.interpolation;
    tracks[t].times = times;
    tracks[t].where = c.where;
    for (size_t k = 0; k < times.size(); ++k)
      for (size_t part = 0; part < perKey; ++part)
        tracks[t].values.push_back(float(v[(k * perKey + part) * targets + t]));
  }
  return tracks;
}

}  // namespace

AnimationTracks readAnimations(const Document& doc, const AccessorReader& reader,
                               std::vector<std::string>* warnings) {
  AnimationTracks tracks;
  for (const Animation& anim : doc.animations) {
    for (const AnimationChannel& c : anim.channels) {
      if (c.node < 0) continue;
      const AnimationSampler& s = anim.samplers[size_t(c.sampler)];
      if (c.path == AnimationPath::Weights) {
        const Node& node = doc.nodes[size_t(c.node)];
        if (node.mesh < 0 || doc.meshes[size_t(node.mesh)].targetCount == 0) {
          warnings->push_back(c.where.str() + ": node " + std::to_string(c.node) +
                              " has no mesh with morph targets; its weights channel is ignored");
          continue;
        }
        if (tracks.weights.count(c.node)) {
          warnings->push_back(c.where.str() + ": node " + std::to_string(c.node) +
                              " weights are already animated by an earlier animation; ignored");
          continue;
        }
        tracks.weights[c.node] = readWeightTracks(s, c, doc, reader);
        continue;
      }
      NodeTracks& t = tracks.nodes[c.node];
      bool taken = c.path == AnimationPath::Translation ? !t.translation.empty()
                   : c.path == AnimationPath::Rotation  ? !t.rotation.empty()
                                                        : !t.scale.empty();
      if (taken) {
        warnings->push_back(c.where.str() + ": node " + std::to_string(c.node) +
                            " is already animated by an earlier animation; ignored");
        continue;
      }
      if (c.path == AnimationPath::Translation)
        fillTrack(&t.translation, s, c, doc, reader);
      else if (c.path == AnimationPath::Rotation)
        fillTrack(&t.rotation, s, c, doc, reader);
      else
        fillTrack(&t.scale, s, c, doc, reader);
    }
  }
  return tracks;
}

}  // namespace glint::gltf
