// Checked access to scene JSON: parsing with comments and duplicate-key detection, and a reader
// that knows each value's field path so every error names the file and the field.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "src/core/math.h"

namespace pt {

// Keeps the file's key order, so materials are indexed in the order they are written.
using Json = nlohmann::ordered_json;

// Parses JSON text with // and /* */ comments. Throws SceneError for malformed text and for a
// key given twice in one object (nlohmann would silently keep the last one).
Json ParseSceneJson(const std::string& text, const std::string& file);

// An allowed interval for a number; open or closed at each end.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loOpen = false, hiOpen = false;

  static Range Any() { return {}; }
  static Range Unit() { return {0.0, 1.0}; }
  static Range NonNegative() { return {0.0}; }
  static Range Positive() { return {0.0, std::numeric_limits<double>::infinity(), true}; }
  static Range Closed(double lo, double hi) { return {lo, hi}; }

  bool Contains(double v) const;
  std::string Describe() const;  // "[0, 1]", "> 0", ">= 0"
};

std::string FormatNumber(double v);  // shortest readable form for messages

// Throws SceneError("file: path: what").
[[noreturn]] void FailAt(const std::string& file, const std::string& path, const std::string& what);

// Reads checked values out of a JSON value that lives at a known path of a known file.
class JsonValue {
 public:
  JsonValue(const Json& json, std::string path, const std::string& file)
      : json_(&json), path_(std::move(path)), file_(&file) {}

  const Json& Raw() const { return *json_; }
  const std::string& Path() const { return path_; }
  const std::string& File() const { return *file_; }
  [[noreturn]] void Fail(const std::string& what) const { FailAt(*file_, path_, what); }

  float Number(Range range = Range::Any()) const;           // finite, inside range
  int64_t Integer(int64_t lo, int64_t hi) const;            // integral, inside [lo, hi]
  vec3 Vec3(Range range = Range::Any()) const;              // 3 finite numbers
  std::string String() const;
  bool Bool() const;
  size_t ArraySize() const;                                  // checks it is an array
  JsonValue Element(size_t i) const;                         // path "x[i]"

 private:
  const Json* json_;
  std::string path_;
  const std::string* file_;
};

// A JSON object: fields by name, each read marking its path. Unknown keys are refused by
// AllowOnly, which each parse function calls first so a typo reads as one.
class JsonObject {
 public:
  explicit JsonObject(const JsonValue& value);  // throws unless it is an object

  const std::string& Path() const { return value_.Path(); }
  const std::string& File() const { return value_.File(); }
  std::string FieldPath(const std::string& key) const;
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const;
  [[noreturn]] void FailHere(const std::string& what) const { value_.Fail(what); }

  // Refuses any key not in the list; 'what' names the kind of object for the message.
  void AllowOnly(std::initializer_list<const char*> keys, const std::string& what) const;

  bool Has(const std::string& key) const;
  JsonValue Field(const std::string& key) const;  // required: throws when missing

  float Number(const std::string& key, Range range = Range::Any()) const;
  float NumberOr(const std::string& key, float fallback, Range range = Range::Any()) const;
  int64_t Integer(const std::string& key, int64_t lo, int64_t hi) const;
  int64_t IntegerOr(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const;
  vec3 Vec3(const std::string& key, Range range = Range::Any()) const;
  vec3 Vec3Or(const std::string& key, vec3 fallback, Range range = Range::Any()) const;
  std::string String(const std::string& key) const;
  bool BoolOr(const std::string& key, bool fallback) const;
  JsonObject Object(const std::string& key) const;

 private:
  JsonValue value_;
};

}  // namespace pt
