#include "src/io/scene_json.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "src/io/scene_loader.h"

namespace pt {
namespace {

// One open object or array while parsing: the keys seen so far (objects) or the element count.
struct ParseFrame {
  bool isObject;
  std::set<std::string> keys;
  std::string currentKey;
  int64_t index = -1;
};

// The path of the value the innermost frame is at, over frames [0, count).
std::string FramesPath(const std::vector<ParseFrame>& frames, size_t count) {
  std::string path;
  for (size_t i = 0; i < count; ++i) {
    const ParseFrame& f = frames[i];
    if (f.isObject) {
      if (f.currentKey.empty()) break;
      path += (path.empty() ? "" : ".") + f.currentKey;
    } else {
      if (f.index < 0) break;
      // append() rather than "[" + ...: GCC 12 gives a false -Wrestrict warning on that at -O3.
      path.append("[").append(std::to_string(f.index)).append("]");
    }
  }
  return path;
}

// nlohmann prefixes "[json.exception.parse_error.101] "; users need only the rest.
std::string StripExceptionId(const std::string& what) {
  size_t close = what.find("] ");
  return (what.rfind("[json.exception", 0) == 0 && close != std::string::npos)
             ? what.substr(close + 2)
             : what;
}

const char* TypeName(const Json& j) { return j.type_name(); }

bool IsTokenChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
}

// The bare word or number the parser stopped in (byteAfter: its `byte`, one past the last
// character read), and whether it starts a value (after '[', ',' or ':'), not a stray token.
struct FailedToken {
  std::string text;
  char before = 0;  // the character before it, whitespace skipped
};

FailedToken TokenAt(const std::string& json, size_t byteAfter) {
  size_t end = std::min(byteAfter, json.size()), start = end;
  if (start > 0 && !IsTokenChar(json[start - 1])) return {};
  while (start > 0 && IsTokenChar(json[start - 1])) --start;
  while (end < json.size() && IsTokenChar(json[end])) ++end;
  FailedToken token{json.substr(start, end - start)};
  size_t b = start;
  while (b > 0 && std::isspace(static_cast<unsigned char>(json[b - 1]))) --b;
  if (b > 0) token.before = json[b - 1];
  return token;
}

// NaN, Infinity, inf in any case and sign: numbers JavaScript knows but JSON does not.
bool IsNonFiniteWord(std::string word) {
  if (!word.empty() && (word[0] == '-' || word[0] == '+')) word.erase(0, 1);
  for (char& c : word) c = char(std::tolower(static_cast<unsigned char>(c)));
  return word == "nan" || word == "inf" || word == "infinity";
}

}  // namespace

void FailAt(const std::string& file, const std::string& path, const std::string& what) {
  throw SceneError(file, path, what);
}

std::string FormatNumber(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.10g", v);
  return buf;
}

bool Range::Contains(double v) const {
  bool aboveLo = loOpen ? v > lo : v >= lo;
  bool belowHi = hiOpen ? v < hi : v <= hi;
  return aboveLo && belowHi;
}

std::string Range::Describe() const {
  bool loInf = std::isinf(lo), hiInf = std::isinf(hi);
  if (loInf && hiInf) return "any finite number";
  if (hiInf) return std::string(loOpen ? "> " : ">= ") + FormatNumber(lo);
  if (loInf) return std::string(hiOpen ? "< " : "<= ") + FormatNumber(hi);
  return std::string(loOpen ? "(" : "[") + FormatNumber(lo) + ", " + FormatNumber(hi) +
         (hiOpen ? ")" : "]");
}

// Scenes nest ~6 deep. nlohmann copies (ordered_map growth) and compares values recursively,
// so a deeper value is refused before it can exhaust the stack.
constexpr size_t kMaxNesting = 128;

Json ParseSceneJson(const std::string& text, const std::string& file) {
  std::vector<ParseFrame> frames;
  auto elementStarts = [&frames, &file] {
    if (!frames.empty() && !frames.back().isObject) frames.back().index++;
    if (frames.size() >= kMaxNesting) {
      FailAt(file, FramesPath(frames, 8) + (frames.size() > 8 ? "..." : ""),
             "nested more than " + std::to_string(kMaxNesting) + " levels deep");
    }
  };
  Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        elementStarts();
        frames.push_back(ParseFrame{true, {}, {}, -1});
        break;
      case Json::parse_event_t::array_start:
        elementStarts();
        frames.push_back(ParseFrame{false, {}, {}, -1});
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        frames.pop_back();
        break;
      case Json::parse_event_t::key: {
        ParseFrame& top = frames.back();
        std::string key = parsed.get<std::string>();
        if (!top.keys.insert(key).second) {
          std::string owner = FramesPath(frames, frames.size() - 1);
          top.currentKey = key;
          FailAt(file, FramesPath(frames, frames.size()),
                 "duplicate key \"" + key + "\" in " + (owner.empty() ? "the top level" : owner));
        }
        top.currentKey = key;
        break;
      }
      case Json::parse_event_t::value:
        elementStarts();
        break;
    }
    return true;
  };
  try {
    return Json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const Json::out_of_range& e) {
    // A number too large for a double ("1e999"): the value being read is the failing one.
    if (!frames.empty() && !frames.back().isObject) frames.back().index++;
    FailAt(file, FramesPath(frames, frames.size()),
           StripExceptionId(e.what()) + " (not a finite number)");
  } catch (const Json::parse_error& e) {
    FailedToken token = TokenAt(text, e.byte);
    // A value that failed to parse after '[' or ',' is the array's next element, not its
    // last good one (nlohmann says "while parsing value" when no value came of the token).
    bool valueFailed = std::string(e.what()).find("while parsing value") != std::string::npos;
    bool startsValue = token.before == '[' || token.before == ',' || token.before == ':';
    bool inArray = !frames.empty() && !frames.back().isObject;
    if (valueFailed && inArray && token.before != ':') frames.back().index++;
    std::string near = FramesPath(frames, frames.size());
    if (valueFailed && startsValue && IsNonFiniteWord(token.text)) {
      FailAt(file, near, token.text + " is not a finite number (JSON has no NaN or Infinity)");
    }
    FailAt(file, "",
           "malformed JSON" + (near.empty() ? std::string() : " near " + near) + ": " +
               StripExceptionId(e.what()));
  }
}

// ---- JsonValue -----------------------------------------------------------------------------

float JsonValue::Number(Range range) const {
  if (!json_->is_number()) Fail(std::string("expected a number, got ") + TypeName(*json_));
  double v = json_->get<double>();
  if (!std::isfinite(v)) Fail(FormatNumber(v) + " is not a finite number");
  if (!range.Contains(v)) {
    bool interval = !std::isinf(range.lo) && !std::isinf(range.hi);
    Fail(FormatNumber(v) + (interval ? " is outside " : " must be ") + range.Describe());
  }
  float f = static_cast<float>(v);
  if (!std::isfinite(f)) Fail(FormatNumber(v) + " is too large for a float");
  return f;
}

int64_t JsonValue::Integer(int64_t lo, int64_t hi) const {
  auto outside = [&](const std::string& value) {
    Fail(value + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  };
  int64_t v = 0;
  if (json_->is_number_unsigned()) {
    uint64_t u = json_->get<uint64_t>();
    if (u > uint64_t(hi)) outside(std::to_string(u));
    v = int64_t(u);
  } else if (json_->is_number_integer()) {
    v = json_->get<int64_t>();
  } else if (json_->is_number_float()) {
    // 1e3 means 1000; 1.5 is not an integer.
    double d = json_->get<double>();
    if (d != std::floor(d)) Fail("expected an integer, got " + FormatNumber(d));
    if (d < double(lo) || d > double(hi)) outside(FormatNumber(d));
    v = int64_t(d);
  } else {
    Fail(std::string("expected an integer, got ") + TypeName(*json_));
  }
  if (v < lo || v > hi) outside(std::to_string(v));
  return v;
}

vec3 JsonValue::Vec3(Range range) const {
  if (!json_->is_array() || json_->size() != 3) {
    std::string got = json_->is_array() ? "an array of " + std::to_string(json_->size())
                                        : std::string(TypeName(*json_));
    Fail("expected an array of 3 numbers, got " + got);
  }
  return vec3(Element(0).Number(range), Element(1).Number(range), Element(2).Number(range));
}

std::string JsonValue::String() const {
  if (!json_->is_string()) Fail(std::string("expected a string, got ") + TypeName(*json_));
  return json_->get<std::string>();
}

bool JsonValue::Bool() const {
  if (!json_->is_boolean()) Fail(std::string("expected true or false, got ") + TypeName(*json_));
  return json_->get<bool>();
}

size_t JsonValue::ArraySize() const {
  if (!json_->is_array()) Fail(std::string("expected an array, got ") + TypeName(*json_));
  return json_->size();
}

JsonValue JsonValue::Element(size_t i) const {
  return JsonValue((*json_)[i], path_ + "[" + std::to_string(i) + "]", *file_);
}

// ---- JsonObject ----------------------------------------------------------------------------

JsonObject::JsonObject(const JsonValue& value) : value_(value) {
  if (!value.Raw().is_object()) {
    value.Fail(std::string("expected an object, got ") + TypeName(value.Raw()));
  }
}

std::string JsonObject::FieldPath(const std::string& key) const {
  return Path().empty() ? key : Path() + "." + key;
}

void JsonObject::Fail(const std::string& key, const std::string& what) const {
  FailAt(File(), FieldPath(key), what);
}

void JsonObject::AllowOnly(std::initializer_list<const char*> keys, const std::string& what) const {
  for (const auto& item : value_.Raw().items()) {
    bool known = false;
    for (const char* k : keys) known = known || item.key() == k;
    if (known) continue;
    std::string list;
    for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
    Fail(item.key(), "unknown field \"" + item.key() + "\" (" + what + " has: " + list + ")");
  }
}

bool JsonObject::Has(const std::string& key) const { return value_.Raw().contains(key); }

JsonValue JsonObject::Field(const std::string& key) const {
  auto it = value_.Raw().find(key);
  if (it == value_.Raw().end()) Fail(key, "missing required field \"" + key + "\"");
  return JsonValue(*it, FieldPath(key), File());
}

float JsonObject::Number(const std::string& key, Range range) const {
  return Field(key).Number(range);
}

float JsonObject::NumberOr(const std::string& key, float fallback, Range range) const {
  return Has(key) ? Number(key, range) : fallback;
}

int64_t JsonObject::Integer(const std::string& key, int64_t lo, int64_t hi) const {
  return Field(key).Integer(lo, hi);
}

int64_t JsonObject::IntegerOr(const std::string& key, int64_t fallback, int64_t lo,
                              int64_t hi) const {
  return Has(key) ? Integer(key, lo, hi) : fallback;
}

vec3 JsonObject::Vec3(const std::string& key, Range range) const { return Field(key).Vec3(range); }

vec3 JsonObject::Vec3Or(const std::string& key, vec3 fallback, Range range) const {
  return Has(key) ? Vec3(key, range) : fallback;
}

std::string JsonObject::String(const std::string& key) const { return Field(key).String(); }

bool JsonObject::BoolOr(const std::string& key, bool fallback) const {
  return Has(key) ? Field(key).Bool() : fallback;
}

JsonObject JsonObject::Object(const std::string& key) const { return JsonObject(Field(key)); }

}  // namespace pt
