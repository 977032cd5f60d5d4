// Scene input helpers: one-line errors, file reading and strict JSON (typed, range-checked values,
// unknown-key detection).
// Every failure is a SceneError "<origin>: <json path>: <problem>" on one line.
#pragma once
#include <nlohmann/json.hpp>
#include <glm/glm.hpp>
#include <cstdint>
#include <set>
#include <string>
#include <vector>
#include "scenes/scene.hpp"

namespace vs {

using Json = nlohmann::json;

// Replaces line breaks and tabs by spaces and trims, so that a message stays on one line.
std::string oneLine(const std::string& text);

// Removes nlohmann's "[json.exception.parse_error.101] " tags from a message.
std::string withoutExceptionTags(std::string message);

// Throws SceneError "<origin>: <path>: <problem>" ("<origin>: <problem>" when path is empty).
[[noreturn]] void throwSceneError(const std::string& origin, const std::string& path,
                                  const std::string& problem);

// The candidate closest to `word` by edit distance, or "" when none is plausibly a typo of it.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" or "".
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

// Reads a whole file into `contents`; on failure returns false and sets `error` (e.g. the errno text).
bool readFile(const std::string& path, std::string& contents, std::string& error);

// Parses JSON text; malformed text, number overflow and duplicate object keys are SceneErrors.
Json parseJsonStrict(const std::string& text, const std::string& origin);

// Allowed interval for a number; the bounds are inclusive or exclusive.
struct Range {
  double lo = -1e300, hi = 1e300;
  bool loInclusive = true, hiInclusive = true;

  static Range any() { return {}; }
  static Range atLeast(double lo) { return {lo, 1e300, true, true}; }
  static Range above(double lo) { return {lo, 1e300, false, true}; }
  static Range closed(double lo, double hi) { return {lo, hi, true, true}; }
  static Range open(double lo, double hi) { return {lo, hi, false, false}; }
  static Range closedOpen(double lo, double hi) { return {lo, hi, true, false}; }
  static Range openClosed(double lo, double hi) { return {lo, hi, false, true}; }
  bool contains(double v) const;
  std::string describe() const;  // e.g. "> 0" or "in (0, 180)"
};

// Formats a number for messages (shortest form that reads back well).
std::string formatNumber(double v);

// A JSON location (origin + path) used for values that are not members of an object (array items).
struct JsonLocation {
  std::string origin, path;
  JsonLocation child(const std::string& key) const;
  JsonLocation item(size_t index) const;
  [[noreturn]] void fail(const std::string& problem) const { throwSceneError(origin, path, problem); }
};

// Typed readers for a value at a location. Numbers must be finite and representable as float.
double readNumber(const Json& value, const JsonLocation& at, Range range);
int64_t readInteger(const Json& value, const JsonLocation& at, int64_t lo, int64_t hi);
glm::vec3 readVec3(const Json& value, const JsonLocation& at, Range range);
glm::vec2 readVec2(const Json& value, const JsonLocation& at, Range range);
std::string readString(const Json& value, const JsonLocation& at);

// Reads the members of one JSON object. Every key looked up (present or not) becomes a known key;
// finish() rejects any other key, so call it after all look-ups.
class ObjectReader {
 public:
  ObjectReader(const Json& value, JsonLocation at);  // throws unless value is an object

  const JsonLocation& location() const { return at_; }
  JsonLocation locationOf(const std::string& key) const { return at_.child(key); }
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

  // Registers every key this object may have up front. Then a missing required key is reported as a
  // misspelling of a present, undeclared key when one is close (e.g. "intensty" for "intensity").
  void declare(const std::vector<std::string>& keys) { knownKeys_.insert(keys.begin(), keys.end()); }

  // Fails when a present, undeclared key looks like a misspelling of `key` (call before reporting it missing).
  void failOnMisspellingOf(const std::string& key) const;

  bool has(const std::string& key);
  const Json& required(const std::string& key);  // fails when missing
  const Json* optional(const std::string& key);  // nullptr when missing

  double number(const std::string& key, Range range);
  double number(const std::string& key, double fallback, Range range);
  int64_t integer(const std::string& key, int64_t lo, int64_t hi);
  int64_t integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi);
  glm::vec3 vec3(const std::string& key, Range range);
  glm::vec3 vec3(const std::string& key, glm::vec3 fallback, Range range);
  glm::vec2 vec2(const std::string& key, glm::vec2 fallback, Range range);
  // A number (the same for r, g and b) or an [r, g, b] triple.
  glm::vec3 rgb(const std::string& key, float fallback, Range range);
  std::string string(const std::string& key);
  std::string string(const std::string& key, const std::string& fallback);
  // One of `options`; fails with the list of options otherwise.
  std::string choice(const std::string& key, const std::vector<std::string>& options,
                     const std::string& fallback);
  bool boolean(const std::string& key, bool fallback);

  // Fails when `key` is present, with `reason` (for keys that only apply in other cases).
  void forbid(const std::string& key, const std::string& reason);
  // Fails on the first key that was never looked up, suggesting the closest known key.
  void finish() const;

 private:
  const Json& object_;
  JsonLocation at_;
  std::set<std::string> knownKeys_;
};

}  // namespace vs
