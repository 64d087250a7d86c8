// glint — keyframed animation: tracks of (time, value) keys, the node hierarchy glTF animates,
// and their evaluation at any time.
//
// Times are seconds. A frame f of a sequence is at time f / fps; a ray's time inside the
// shutter maps to frameTime + open + rayTime · (close - open). Everything that moves is
// evaluated here, from the description; scenes/build samples transforms over the shutter
// into geometry/motion.h's AnimatedTransform keys.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "geometry/math.h"
#include "geometry/motion.h"
#include "scenes/errors.h"

namespace glint {

enum class Interpolation {
  Step,         // the value of the last key at or before t (glTF STEP)
  Linear,       // linear; slerp for rotations (glTF LINEAR)
  CubicSpline,  // Hermite with per-key in/out tangents (glTF CUBICSPLINE)
  Smooth,       // Catmull-Rom through the keys (sidecar "smooth"): C1, passes every key
};

// Keys sorted by strictly increasing time. Before the first key the first value holds, after
// the last the last. CubicSpline stores three values per key: in-tangent, value, out-tangent
// (glTF's layout); the others one.
template <class T>
struct Track {
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;
  std::vector<T> values;
  SourceLocation where;

  bool empty() const { return times.empty(); }
  float startTime() const { return times.empty() ? 0.0f : times.front(); }
  float endTime() const { return times.empty() ? 0.0f : times.back(); }
};

// Evaluation (scenes/animation.cpp). An empty track is a caller error (asserted). Rotations
// are unit quaternions: Linear is slerp along the shorter arc, CubicSpline and Smooth are
// evaluated per component (Smooth with each key moved into the hemisphere of the previous one)
// and renormalised.
float evaluate(const Track<float>& track, double time);
Vec2f evaluate(const Track<Vec2f>& track, double time);
Vec3f evaluate(const Track<Vec3f>& track, double time);
Quaternion evaluate(const Track<Quaternion>& track, double time);

// A node of the transform hierarchy. Its local transform is `matrix` when the file gave a
// matrix (glTF forbids animating those), else T · R · S from the rest values, each replaced
// by its track where one exists. The rotation comes from `angleTrack` (degrees about
// `rotationAxis`: the sidecar's form, which can turn by more than 180 degrees between two
// keys) when that is set, else from `rotationTrack`, else from `rotation`.
struct NodeDesc {
  std::string name;
  int parent = -1;  // index into SceneDescription::nodes
  bool hasMatrix = false;
  Transform matrix;
  Vec3f translation{0, 0, 0};
  Quaternion rotation;
  Vec3f scale{1, 1, 1};
  Track<Vec3f> translationTrack;
  Track<Quaternion> rotationTrack;
  Track<Vec3f> scaleTrack;
  Vec3f rotationAxis{0, 1, 0};  // unit length
  Track<float> angleTrack;      // degrees
  SourceLocation where;

  bool hasTracks() const {
    return !translationTrack.empty() || !rotationTrack.empty() || !scaleTrack.empty() ||
           !angleTrack.empty();
  }
  Transform localAt(double time) const;
};

// Whether node `node` or any of its ancestors has a track (false for -1).
bool isAnimated(const std::vector<NodeDesc>& nodes, int node);
// World-from-node at `time`: the local transforms along the parent chain, root first. The
// identity for node -1.
Transform worldFromNode(const std::vector<NodeDesc>& nodes, int node, double time);
// The time span covered by all tracks of all nodes, {0, 0} when nothing is keyed.
std::pair<double, double> animationRange(const std::vector<NodeDesc>& nodes);

// The sidecar's names of the interpolation modes ("linear", "step", "smooth"; glTF's
// CUBICSPLINE is "cubicspline").
const char* interpolationName(Interpolation interpolation);

}  // namespace glint
