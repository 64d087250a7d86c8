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
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "geometry/math.h"
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
// Value conversion
// ---------------------------------------------------------------------------------------------

// Converts one JSON value found at `where` to T, or throws a SceneError at `where`. Supported:
// bool, int, uint64_t, float, std::string, Vec2f, Vec3f (= Rgb), Transform. `range` applies to
// numbers (each component of a vector) and is ignored for the other types.
template <class T>
T readValue(const nlohmann::json& value, const SourceLocation& where, const Range& range = {});

// The supported types (defined in json_reader.cpp; other types fail to link).
#define GLINT_JSON_READ_VALUE(T) \
  template <>                    \
  T readValue<T>(const nlohmann::json& value, const SourceLocation& where, const Range& range)
GLINT_JSON_READ_VALUE(bool);
GLINT_JSON_READ_VALUE(int);
GLINT_JSON_READ_VALUE(uint64_t);
GLINT_JSON_READ_VALUE(float);
GLINT_JSON_READ_VALUE(std::string);
GLINT_JSON_READ_VALUE(Vec2f);
GLINT_JSON_READ_VALUE(Vec3f);
GLINT_JSON_READ_VALUE(Transform);
#undef GLINT_JSON_READ_VALUE

// A 4x4 transform: 16 numbers (row-major), 4 rows of 4 numbers, or a list of operations applied
// in order, the first one first:
//   [{"scale": 2}, {"rotate": {"axis": [0, 1, 0], "degrees": 90}}, {"translate": [1, 0, 0]}]
// Operations: translate [x,y,z]; rotate {axis, degrees}; scale s or [x,y,z]; shear {xy, xz,
// yx, yz, zx, zy} (x' = x + xy y + xz z, ...; unset factors 0); matrix (either matrix form). Singular, non-affine or non-finite matrices are errors at their pointer.
Transform readTransform(const nlohmann::json& value, const SourceLocation& where);

// One element of an array read through a JsonReader, with its location.
struct JsonItem {
  const nlohmann::json* value = nullptr;
  SourceLocation where;

  template <class T>
  T as(const Range& range = {}) const {
    return readValue<T>(*value, where, range);
  }
};

// ---------------------------------------------------------------------------------------------
// JsonReader
// ---------------------------------------------------------------------------------------------

class JsonReader {
 public:
  // Reads the JSON object `object` found at `where`; throws "expected object, got X" when it
  // is not an object. `object` must outlive the reader.
  JsonReader(const nlohmann::json& object, SourceLocation where);
  JsonReader(JsonReader&&) = default;
  JsonReader& operator=(JsonReader&&) = default;

  const SourceLocation& where() const { return where_; }
  SourceLocation where(std::string_view key) const { return where_.child(std::string(key)); }
  const nlohmann::json& json() const { return *object_; }
  // True when `key` is present. Does not count as reading it.
  bool has(std::string_view key) const;

  // --- scalars and vectors (see readValue for the supported types) ---
  // Required: a missing key is "/parent: missing required key 'key'".
  template <class T>
  T get(std::string_view key, const Range& range = {}) {
    return readValue<T>(require(key), where(key), range);
  }
  // With a fallback for a missing key.
  template <class T>
  T get(std::string_view key, const T& fallback, const Range& range = {}) {
    const nlohmann::json* v = take(key);
    return v ? readValue<T>(*v, where(key), range) : fallback;
  }
  // Empty when the key is missing.
  template <class T>
  std::optional<T> optional(std::string_view key, const Range& range = {}) {
    const nlohmann::json* v = take(key);
    if (!v) return std::nullopt;
    return readValue<T>(*v, where(key), range);
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
  // never read: "/render/spq: unknown key 'spq'; did you mean 'spp'?".
  void finish() const;

 private:
  void markKnown(std::string_view key);

  const nlohmann::json* object_;
  SourceLocation where_;
  std::set<std::string, std::less<>> read_;   // keys taken
  std::set<std::string, std::less<>> known_;  // keys asked for, present or not
  std::vector<std::unique_ptr<JsonReader>> children_;
};

}  // namespace glint
