// glint tests — the invariance net (issue 49, item 4): a whole scene moved, scaled, turned or
// mirrored must render the same image. This header holds the pieces the tests share:
//   * Similarity: a map x -> s R x + t of space (R orthogonal, det +-1), in double;
//   * transformScene: a glint JSON scene rewritten so that everything in it undergoes that map,
//     either by editing every position-like key ("edit", translations only) or by appending the
//     map to each object's transform ("root");
//   * compareFilms: the comparison the net judges by, with its tolerances;
//   * renderScene: a JSON scene rendered in-process, as glint renders it.
#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "renderer/features.h"
#include "renderer/film.h"

namespace glint::invariance {

using Json = nlohmann::json;

struct V3 {
  double x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 normalized(V3 v);
V3 toV3(const Json& j);  // a 3-array
Json toJson(V3 v);

// x -> s R x + t.
struct Similarity {
  std::string name;  // e.g. "translate-edit/1e6", "rotate/1"
  double s = 1;
  std::array<std::array<double, 3>, 3> R{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  V3 t;
  // The transform operation that applies the whole map ({"translate": ...}, {"scale": s},
  // {"rotate": ...} or {"matrix": ...}), and the one of its linear part alone (null: none).
  Json op, linearOp;

  V3 point(V3 p) const { return rotate(p) * s + t; }
  V3 vector(V3 v) const { return rotate(v) * s; }
  V3 rotate(V3 v) const;
  double handedness() const;  // det R: +1, or -1 for a reflection
  bool turns() const;         // R is not the identity
  bool moves() const { return t.x != 0 || t.y != 0 || t.z != 0; }
};

Similarity identity();
Similarity translation(V3 d);
Similarity scaling(double s);
// Right-handed rotation by `degrees` about `axis` (through the origin).
Similarity rotation(V3 axis, double degrees);
// The reflection in the plane through the origin with normal `n` (det -1).
Similarity reflection(V3 n);
// A rotation about an axis drawn from `seed` (splitmix64: the same on every machine), by an
// angle drawn in [20, 340] degrees.
Similarity randomRotation(uint64_t seed);

// How a translation reaches the objects.
enum class Placement {
  Edit,  // every position-like key rewritten (centre, min/max, point, corner, the last
         // `translate` of a transform, animation translation keys, ...)
  Root,  // the map appended to each object's transform (glTF entries, objects, media regions)
};

// What transformScene needs to know about the scene that the JSON alone does not say.
struct SceneFacts {
  // Each camera placed by position/look_at, by name: its camera-to-world matrix at the scene
  // time, row-major, and its focus distance (what glint derived). A reflection cannot be
  // written with position/look_at (they always give a right-handed frame), so such cameras
  // become `transform` matrices under one.
  std::map<std::string, std::array<std::array<double, 4>, 4>> cameraFrames;
  std::map<std::string, double> focusDistances;
  // glTF materials with KHR_materials_volume, by name: that extension's JSON (its
  // attenuationDistance is a length, which a scale must change through a material override).
  std::map<std::string, Json> gltfVolumes;
  // Lights that come from glTF files (KHR_lights_punctual): their intensities cannot be
  // rescaled from the scene file.
  int gltfPunctualLights = 0;
};

// The scene `scene` (a glint .json scene; glTF files only through its `gltf` list) with
// everything in it moved by `x`. `mode` Edit is for translations only. Appends a line to
// `notes` for every adjustment beyond moving positions (intensities, densities, texture
// offsets, ...). Throws std::runtime_error for anything it does not know how to move, so a new
// key in a scene fails the net instead of passing it unmoved.
Json transformScene(const Json& scene, const Similarity& x, Placement mode, const SceneFacts& facts,
                    std::vector<std::string>* notes);

// Why the scene cannot be rotated or mirrored as a whole, one reason a line (empty: it can):
// world-space texture mappings and whole-scene media fields that have no rotation key, and an
// environment map or the studio (which turn only about +Y).
std::vector<std::string> rotationBlockers(const Json& scene);

// Reads a scene's facts with glint's own loader (`file` resolves relative paths).
SceneFacts sceneFacts(const Json& scene, const std::string& file);

// ---- rendering and comparison ----------------------------------------------------------------

// Renders a glint JSON scene in-process on two threads, as `glint render` would; `file` names
// it in messages and resolves its relative paths.
// `features`, when given, receives the built scene's features.
Film renderScene(const Json& scene, const std::string& file, SceneFeatures* features = nullptr);

// The tolerances one comparison uses (see compareFilms).
struct Tolerance {
  double pixel = 0.02;  // per channel, in the squeezed domain below
  int radius = 1;       // pixels (or blocks) an edge may move
  double mean = 0.005;  // relative difference of the mean luminance
  // Independent noise: when the two renders cannot draw the same random numbers for the same
  // light paths (a rotation turns the local frames samples are drawn in), their pixels differ
  // by noise. Then both films are averaged over `block` x `block` pixels first, and each
  // block's tolerance (and the mean's) grows by `sigmas` standard deviations of the
  // difference, from the films' own variance channels. 1 and 0: the same samples, compared
  // pixel by pixel.
  int block = 1;
  double sigmas = 0;
  double meanSigmas = 0;  // the same for the mean (independent noise only: shared samples
                          // make the two means' noise the same)
  double altSigmas = 0;   // compareFilms' `alternates`: multiples of the seed-to-seed difference
};

struct Comparison {
  int width = 0, height = 0;  // of the full films
  int block = 1;              // the tolerance's block size
  int bad = 0;                // pixels (blocks) that fail the window test
  int worstX = -1, worstY = -1;
  double worstExcess = 0;         // how far the worst one is outside the allowed range
  double largestExcess = 0;       // the largest excess of any pixel (block) before the tolerance:
                                  // how close the passing ones came
  double worstA = 0, worstB = 0;  // its radiance (largest channel difference) in a and b
  double maxDiff = 0;             // largest |a - b| of any channel anywhere, in radiance
  int maxDiffX = -1, maxDiffY = -1;
  double maxDiffA = 0, maxDiffB = 0;
  double meanA = 0, meanB = 0;  // mean luminance
  double relMean = 0;           // |meanB - meanA| / meanA
  double meanNoise = 0;         // sigmas x the standard deviation of relMean (independent noise)
  bool nonFinite = false;
  std::vector<uint8_t> badMask;  // width x height, 1 where a pixel failed
  std::string where;             // the first few bad pixels, "(x, y) a vs b"
  bool pixelsPass() const { return bad == 0 && !nonFinite; }
  bool meanPasses(const Tolerance& t) const { return relMean <= t.mean + meanNoise && !nonFinite; }
  bool passes(const Tolerance& t) const { return pixelsPass() && meanPasses(t); }
  std::string summary() const;
};

// The net's judgement of `b` (the transformed scene's image) against `a` (the original's).
// Values are compared per channel in a squeezed domain, v = y / (1 + y) with y = radiance /
// (2 * mean luminance of a): mid-grey of the image at 1/3, highlights compressed, so one
// tolerance serves bright and dark scenes. A pixel fails when its value in one image lies
// outside [min - tol, max + tol] of the other image's values in the (2 radius + 1)^2 window
// around it, in either direction: an edge that moved by up to `radius` pixels passes (its
// values are found nearby), a lost shadow, a speckle of acne, a firefly, a light leak or a
// missing wall does not (no nearby pixel of the other image has that value). This is the
// "no pixel off by more than tol away from edges dilated by radius" rule with the edges taken
// from both images, but an isolated speckle cannot excuse itself as an edge.
//
// `alternates`, when given, are `a` rendered again with other seeds: noise that the films'
// variance does not hold (instant radiosity's one set of VPLs for the whole image) shows as
// the differences between the seeds, and each pixel's (block's) tolerance grows by
// `altSigmas` times their root mean square over the window (the mean's by `meanSigmas` times
// the root mean square of the seeds' differences of means).
Comparison compareFilms(const Film& a, const Film& b, const Tolerance& tol,
                        const std::vector<const Film*>& alternates = {});

// Writes film as EXR and PNG (path without extension); the PNG is best effort.
void writeFilm(const std::string& pathStem, const Film& film);
// Writes a mask (1 = bad) over a dimmed copy of `film` as PNG: where the failures are.
void writeMask(const std::string& path, const Film& film, const std::vector<uint8_t>& mask);

}  // namespace glint::invariance
