// glint — SceneFeatures: the effects a scene calls for.
//
// Computed once from the built scene (detectFeatures, below); it is the only switch for optional
// work (which surface attributes are interpolated, whether shadow rays are traced, later: lens
// sampling, motion time steps, media). `glint info` prints it and `--stats` records it. A scene
// without an effect pays nothing for it. Later issues add flags; keep names short and user-facing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace glint {

enum class Feature : uint32_t {
  Shadows,       // some light casts shadows onto lit (non-eyelight) surfaces
  Textures,      // some material reads an image texture
  VertexColors,  // some material reads COLOR_0
  Emission,      // some material emits light
  Instancing,    // some mesh is placed more than once
  DefaultLight,  // the scene brought no light; the studio environment lights it
  Analytic,      // analytic primitives (Embree user geometry)
  Csg,           // constructive solid geometry trees
  Terrain,       // fractal terrain
  Transparency,  // some surface lets light pass straight through (alpha, transparent eyelight)
  Refraction,    // some surface refracts (glass, glTF transmission)
  Bump,          // some material perturbs its shading normal (bump, normal map, snow)
  Procedural,    // some material reads a procedural (noise) texture
  Lens,          // the camera has an aperture: lens samples, depth of field
  MotionBlur,    // something moves during the shutter: ray times, Embree time steps
  Volumes,       // participating media: transmittance on every ray, in-scattering
  AreaLights,    // some light has an area (quad, disk, sphere, emissive surface): soft shadows
  Environment,   // an environment light surrounds the scene
  Projective,    // a projective textured light (a slide projector)
  Indirect,      // the integrator follows diffuse and glossy bounces (path tracer, VPLs)
  Vpls,          // instant radiosity: virtual point lights from light paths
  Count
};

class SceneFeatures {
 public:
  void set(Feature f, bool on = true) {
    uint32_t bit = 1u << uint32_t(f);
    bits_ = on ? bits_ | bit : bits_ & ~bit;
  }
  bool has(Feature f) const { return bits_ & (1u << uint32_t(f)); }
  // Names of the enabled features, in declaration order ("shadows", "textures", ...).
  std::vector<std::string> names() const;

 private:
  uint32_t bits_ = 0;
};

// The user-facing name of a feature ("motion blur").
const char* featureName(Feature f);

class RenderScene;
struct IntegratorSettings;

// What the builder made that the built scene does not show by itself.
struct BuildNotes {
  bool defaultLight = false;  // the scene brought no light; the builder added the studio
  bool terrain = false;       // a fractal terrain was meshed
};

// The scene's effects, decided in this one place once everything is built (geometry,
// materials, camera, lights, media): what the materials read and do, what lights there are,
// lens and motion from the camera and the instances, media, and what the integrator
// `integrator` resolves to follows (indirect light, VPLs). Every optional code path asks the
// result, never the parts.
SceneFeatures detectFeatures(const RenderScene& scene, const IntegratorSettings& integrator,
                             const BuildNotes& notes);

}  // namespace glint
