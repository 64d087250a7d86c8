// glint — JsonReader: typed, located reading of one JSON object, with an unknown-key check.
//
// Every scene schema (sidecar, glint .json scenes, and the objects later issues add) is read
// through this class, so all of them report errors the same way:
//
//   JsonReader render = root.object("render");            // "/render: expected object, got array"
//   int spp = render.get<int>("spp", 16, kPositive);       // "/render/spp: must be > 0"
//   float fov = cam.get<float>("yfov_degrees", 40, {.gt = 0, .lt = 180});
//   Rgb color = light.get<Rgb>("color", {1, 1, 1}, kNonNegative);
//   std::string op = tm.oneOf("operator", {"none", "ward"}, "none");
//   root.finish();   // "/render/spq: unknown key 'spq'; did you mean 'spp'?"
//
// A reader remembers which keys were read (or asked for); finish() rejects every other key,
// like pbrt-v4's unused-parameter check and Mitsuba's check_unused_parameters, so a typo never
// silently renders the wrong thing. Child readers (object(), objects(), item()) are owned by
// their parent and finished by the parent's finish().
//
// glTF is read by the same class in lenient mode (JsonMode::Lenient, scenes/gltf_document.h):
// glTF allows keys it does not define, "extras" and unknown optional extensions, so there
// finish() accepts every key; the checks on what is read are the same.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "geometry/math.h"
#include "geometry/motion.h"
#include "scenes/animation.h"
#include "scenes/errors.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// Constraints
// ---------------------------------------------------------------------------------------------

// Bounds on a number, checked on every component of a vector. Numbers must always be finite
// as a float; a Range adds bounds, written with designated initializers:
// {.gt = 0}, {.ge = 0, .le = 90}, {.gt = 0, .lt = 180}.
struct Range {
  std::optional<double> gt, ge, lt, le;

  bool contains(double v) const {
    return (!gt || v > *gt) && (!ge || v >= *ge) && (!lt || v < *lt) && (!le || v <= *le);
  }
  bool empty() const { return !gt && !ge && !lt && !le; }
  std::string describe() const;  // "must be > 0", "must be >= 0 and <= 90"
};

inline constexpr Range kPositive{.gt = 0};
inline constexpr Range kNonNegative{.ge = 0};
inline constexpr Range kUnit{.ge = 0, .le = 1};

// The closest of `candidates` to `word` when it is close enough to be a likely typo, else "".
std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates);

// ---------------------------------------------------------------------------------------------
// Modes
// ---------------------------------------------------------------------------------------------

// Strict: glint's own schemas (sidecars, .json scenes). Unread keys are errors (finish()), and
// messages name keys and types tersely: "missing required key 'x'", "expected number, got
// string".
// Lenient: glTF. Keys the reader never asks for are allowed, as glTF allows them (extras,
// unknown optional extensions, properties glint does not use). Messages keep the glTF
// vocabulary glint has always reported and its tests and users know: "missing required
// property 'x'", "expected a number, got string", "expected an array of 3 numbers". There are
// no keyframes, and a double must fit a float (every glTF number becomes one); a strict
// double (the sidecar's scene time) need only be finite.
// Every other check and message is the same in both modes.
enum class JsonMode { Strict, Lenient };

// ---------------------------------------------------------------------------------------------
// Value conversion
// ---------------------------------------------------------------------------------------------

// Converts one JSON value found at `where` to T, or throws a SceneError at `where`. Supported:
// bool, int, uint64_t, float, double, std::string, Vec2f, Vec3f (= Rgb), Quaternion ([x, y, z, w],
// not zero, normalised), Transform. `range` applies to numbers (each component of a vector)
// and is ignored for the other types. `mode` words the type errors (see JsonMode); in lenient
// mode a double must also fit a float (glint keeps glTF's numbers as floats) and is returned as
// written, so that bounds are checked before rounding.
template <class T>
T readValue(const nlohmann::json& value, const SourceLocation& where, const Range& range = {},
            JsonMode mode = JsonMode::Strict);

// The supported types (defined in json_reader.cpp; other types fail to link).
#define GLINT_JSON_READ_VALUE(T)                                                               \
  template <>                                                                                  \
  T readValue<T>(const nlohmann::json& value, const SourceLocation& where, const Range& range, \
                 JsonMode mode)
GLINT_JSON_READ_VALUE(bool);
GLINT_JSON_READ_VALUE(int);
GLINT_JSON_READ_VALUE(uint64_t);
GLINT_JSON_READ_VALUE(float);
GLINT_JSON_READ_VALUE(double);
GLINT_JSON_READ_VALUE(std::string);
GLINT_JSON_READ_VALUE(Vec2f);
GLINT_JSON_READ_VALUE(Vec3f);
GLINT_JSON_READ_VALUE(Quaternion);
GLINT_JSON_READ_VALUE(Transform);
#undef GLINT_JSON_READ_VALUE

// A size, count, byte offset or enumeration code: a non-negative integer. An integral number
// written with a fraction (3.0, as some glTF exporters write counts) is accepted too. Errors:
// "must not be negative (got -3)", "expected a non-negative integer, got string \"three\"".
size_t readSize(const nlohmann::json& value, const SourceLocation& where);

// An index into an array of `count` items called `what`, read as readSize reads: "accessor 7
// does not exist (3 accessors in the file)".
int readIndex(const nlohmann::json& value, const SourceLocation& where, size_t count,
              std::string_view what);

// An array of exactly `n` numbers (each as readValue<double> reads it in `mode`, within
// `range`) into `out`. Strict: "expected an array of 3 numbers, got string", "expected 3 numbers,
// got 2"; lenient: "expected an array of 3 numbers" for both.
void readNumbers(const nlohmann::json& value, const SourceLocation& where, double* out, size_t n,
                 const Range& range = {}, JsonMode mode = JsonMode::Strict);

// A 4x4 transform: 16 numbers (row-major), 4 rows of 4 numbers, or a list of operations applied
// in order, the first one first:
//   [{"scale": 2}, {"rotate": {"axis": [0, 1, 0], "degrees": 90}}, {"translate": [1, 0, 0]}]
// Operations: translate [x,y,z]; rotate {axis, degrees}; scale s or [x,y,z]; shear {xy, xz,
// yx, yz, zx, zy} (x' = x + xy y + xz z, ...; unset factors 0); matrix (either matrix form).
// Singular, non-affine or non-finite matrices are errors at their pointer. `meant`, when
// given, receives the same transform as its author meant (see MeantTransform).
Transform readTransform(const nlohmann::json& value, const SourceLocation& where,
                        MeantTransform* meant = nullptr);

// One element of an array read through a JsonReader, with its location (and the reader's mode,
// which words its errors).
struct JsonItem {
  const nlohmann::json* value = nullptr;
  SourceLocation where;
  JsonMode mode = JsonMode::Strict;

  template <class T>
  T as(const Range& range = {}) const {
    return readValue<T>(*value, where, range, mode);
  }
  size_t asSize() const { return readSize(*value, where); }
  int asIndex(size_t count, std::string_view what) const {
    return readIndex(*value, where, count, what);
  }
};

// ---------------------------------------------------------------------------------------------
// Keyframes
// ---------------------------------------------------------------------------------------------

// Whether `value` is written as keyframes: an object with a "keys" member.
bool isKeyframes(const nlohmann::json& value);

class JsonReader;

// Reads the "keys" and "interpolation" of a keyframe object (the caller's reader `r` may hold
// more keys, e.g. a rotation axis, and finishes it):
//   {"keys": [[t, value], ...], "interpolation": "linear" | "step" | "smooth"}
// Times are seconds, finite and strictly increasing; at least one key. `read` converts one
// value (given its JSON and location).
template <class T, class ReadValue>
Track<T> readTrack(JsonReader& r, ReadValue&& read);

// ---------------------------------------------------------------------------------------------
// JsonReader
// ---------------------------------------------------------------------------------------------

class JsonReader {
 public:
  // Reads the JSON object `object` found at `where`; throws "expected object, got X" when it
  // is not an object. `object` must outlive the reader. With a `time`, numbers and vectors
  // read through get(), optional() and value() may be keyframes (see readTrack), evaluated at
  // that time; without one, keyframes are an error. Child readers share the time.
  JsonReader(const nlohmann::json& object, SourceLocation where,
             std::optional<double> time = std::nullopt);
  // A reader in `mode` (keyframes are not allowed). Child readers share the mode.
  JsonReader(const nlohmann::json& object, SourceLocation where, JsonMode mode);
  // A reader of its own for an array element (from array() or optionalArray()), in the
  // element's mode, without a time. Unlike item(), no parent owns or finishes it: it lives as
  // long as its user keeps it (a strict one is finished by its user). Reading a long array this
  // way holds one element's readers at a time, not all of them until the parent goes (a glTF
  // file can hold 100,000 accessors).
  explicit JsonReader(const JsonItem& element);
  JsonReader(JsonReader&&) = default;
  JsonReader& operator=(JsonReader&&) = default;

  JsonMode mode() const { return mode_; }
  const SourceLocation& where() const { return where_; }
  SourceLocation where(std::string_view key) const { return where_.child(std::string(key)); }
  const nlohmann::json& json() const { return *object_; }
  // The time keyframes are evaluated at (none: keyframes are not allowed).
  std::optional<double> time() const { return time_; }
  // True when `key` is present. Does not count as reading it.
  bool has(std::string_view key) const;

  // --- scalars and vectors (see readValue for the supported types) ---
  // Required: a missing key is "/parent: missing required key 'key'" (lenient: "property").
  template <class T>
  T get(std::string_view key, const Range& range = {}) {
    return value<T>(require(key), where(key), range);
  }
  // With a fallback for a missing key.
  template <class T>
  T get(std::string_view key, const T& fallback, const Range& range = {}) {
    const nlohmann::json* v = take(key);
    return v ? value<T>(*v, where(key), range) : fallback;
  }
  // Empty when the key is missing.
  template <class T>
  std::optional<T> optional(std::string_view key, const Range& range = {}) {
    const nlohmann::json* v = take(key);
    if (!v) return std::nullopt;
    return value<T>(*v, where(key), range);
  }
  // A value taken with take(): like readValue, but float, Vec2f and Vec3f may be keyframes,
  // evaluated at time(). Every key's value must satisfy `range`, and so must the value at
  // time() (a "smooth" curve can overshoot its keys). Lenient readers know no keyframes (glTF
  // has its own animations): {"keys": ...} is then just a value of the wrong type.
  template <class T>
  T value(const nlohmann::json& v, const SourceLocation& at, const Range& range = {}) const {
    if (mode_ == JsonMode::Strict && isKeyframes(v)) {
      if constexpr (std::is_same_v<T, float> || std::is_same_v<T, Vec2f> ||
                    std::is_same_v<T, Vec3f>)
        return keyframed<T>(v, at, range);
      else
        throw SceneError(at, "keyframes are only allowed on numbers and vectors");
    }
    return readValue<T>(v, at, range, mode_);
  }

  // --- sizes, indices and fixed-length number arrays (see readSize, readIndex, readNumbers) ---
  // A required size (count, byte length, enumeration code), or one with a fallback.
  size_t getSize(std::string_view key);
  size_t getSize(std::string_view key, size_t fallback);
  // A required index into `count` items called `what` ("accessor"), or one with a fallback
  // (glTF's -1 for "none").
  int index(std::string_view key, size_t count, std::string_view what);
  int index(std::string_view key, size_t count, std::string_view what, int fallback);
  // Exactly N numbers, required, returned as written (before rounding to float).
  template <size_t N>
  std::array<double, N> numbers(std::string_view key, const Range& range = {}) {
    std::array<double, N> out;
    readNumbers(require(key), where(key), out.data(), N, range, mode_);
    return out;
  }

  // --- enumerations: a string that must be one of `allowed` ---
  std::string oneOf(std::string_view key, const std::vector<std::string>& allowed);
  std::string oneOf(std::string_view key, const std::vector<std::string>& allowed,
                    const std::string& fallback);
  // Mapped to an enum: r.oneOf<LightType>("type", {{"point", LightType::Point}, ...}).
  template <class E>
  E oneOf(std::string_view key, const std::vector<std::pair<std::string, E>>& choices,
          std::optional<E> fallback = std::nullopt) {
    std::vector<std::string> names;
    for (const auto& c : choices) names.push_back(c.first);
    if (fallback && !has(key)) {
      markKnown(key);
      return *fallback;
    }
    std::string name = oneOf(key, names);
    for (const auto& c : choices)
      if (c.first == name) return c.second;
    return choices.front().second;  // unreachable: oneOf() validated the name
  }

  // --- nested objects and arrays ---
  // The object at `key`, read by a child reader that finish() also finishes.
  JsonReader& object(std::string_view key);
  // Same, or nullptr when the key is missing.
  JsonReader* optionalObject(std::string_view key);
  // The elements of the array at `key`; required, or empty when missing for the optional form.
  std::vector<JsonItem> array(std::string_view key);
  std::vector<JsonItem> optionalArray(std::string_view key);
  // A child reader for an object element of an array this reader returned.
  JsonReader& item(const JsonItem& element);
  // The optional array of objects at `key`, each with its child reader (in order).
  std::vector<JsonReader*> objects(std::string_view key);

  // --- escape hatches for custom forms ---
  // The raw value at `key` (marked as read), or nullptr when missing.
  const nlohmann::json* take(std::string_view key);
  // The raw value at `key` (marked as read); throws when missing.
  const nlohmann::json& require(std::string_view key);
  // Accepts `key` without reading it.
  void ignore(std::string_view key) { take(key); }

  // Throws for the first key of this object (then of each child, in creation order) that was
  // never read: "/render/spq: unknown key 'spq'; did you mean 'spp'?". A lenient reader
  // accepts every key: finish() checks nothing (and the reader keeps no record of keys read).
  void finish() const;

 private:
  JsonReader(const nlohmann::json& object, SourceLocation where, std::optional<double> time,
             JsonMode mode);
  JsonReader& child(const nlohmann::json& value, SourceLocation at);
  void markKnown(std::string_view key);
  template <class T>
  T keyframed(const nlohmann::json& v, const SourceLocation& at, const Range& range) const;

  const nlohmann::json* object_;
  SourceLocation where_;
  std::optional<double> time_;
  JsonMode mode_ = JsonMode::Strict;
  std::set<std::string, std::less<>> read_;   // keys taken
  std::set<std::string, std::less<>> known_;  // keys asked for, present or not
  std::vector<std::unique_ptr<JsonReader>> children_;
};

// ---------------------------------------------------------------------------------------------
// Keyframes (templates)
// ---------------------------------------------------------------------------------------------

template <class T, class ReadValue>
Track<T> readTrack(JsonReader& r, ReadValue&& read) {
  Track<T> track;
  track.where = r.where();
  track.interpolation = r.oneOf<Interpolation>("interpolation",
                                               {{"linear", Interpolation::Linear},
                                                {"step", Interpolation::Step},
                                                {"smooth", Interpolation::Smooth}},
                                               Interpolation::Linear);
  std::vector<JsonItem> keys = r.array("keys");
  if (keys.empty()) throw SceneError(r.where("keys"), "needs at least one key");
  for (const JsonItem& key : keys) {
    if (!key.value->is_array() || key.value->size() != 2)
      throw SceneError(key.where, "a key is [time, value]");
    SourceLocation at = key.where.child(size_t(0));
    float t = readValue<float>((*key.value)[0], at);
    if (!track.times.empty() && !(t > track.times.back()))
      throw SceneError(at, "key times must increase strictly (the previous key is at " +
                               std::to_string(track.times.back()) + ")");
    track.times.push_back(t);
    track.values.push_back(read((*key.value)[1], key.where.child(size_t(1))));
  }
  return track;
}

template <class T>
T JsonReader::keyframed(const nlohmann::json& v, const SourceLocation& at,
                        const Range& range) const {
  if (!time_) throw SceneError(at, "keyframes are not allowed here");
  JsonReader r(v, at);
  Track<T> track = readTrack<T>(r, [&](const nlohmann::json& x, const SourceLocation& w) {
    return readValue<T>(x, w, range);
  });
  r.finish();
  T result = evaluate(track, *time_);
  if constexpr (std::is_same_v<T, float>) {
    if (!range.contains(result))
      throw SceneError(at, "the keyframed value at time " + std::to_string(*time_) + " is " +
                               std::to_string(result) + ": " + range.describe() +
                               " (a smooth curve overshoots its keys; add keys or use linear)");
  } else {
    for (int i = 0; i < (std::is_same_v<T, Vec2f> ? 2 : 3); ++i)
      if (!range.contains(result[i]))
        throw SceneError(at, "the keyframed value at time " + std::to_string(*time_) +
                                 " has component " + std::to_string(i) + " = " +
                                 std::to_string(result[i]) + ": " + range.describe() +
                                 " (a smooth curve overshoots its keys; add keys or use linear)");
  }
  return result;
}

}  // namespace glint
