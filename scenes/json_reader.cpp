#include "scenes/json_reader.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace vs {

std::string oneLine(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    bool isBreak = c == '\n' || c == '\r' || c == '\t';
    if (isBreak) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += c;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

void throwSceneError(const std::string& origin, const std::string& path, const std::string& problem) {
  std::string message = origin + ": ";
  if (!path.empty()) message += path + ": ";
  throw SceneError(oneLine(message + problem));
}

static size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> previous(b.size() + 1), current(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  // Score = edit distance; a candidate that starts with the word ("fov" -> "fov_y_deg") ranks first.
  std::string best;
  double bestScore = 1e9;
  for (const std::string& candidate : candidates) {
    bool isPrefix = word.size() >= 2 && candidate.size() > word.size() && candidate.compare(0, word.size(), word) == 0;
    double score = isPrefix ? 0.5 : double(editDistance(word, candidate));
    if (score < bestScore) {
      bestScore = score;
      best = candidate;
    }
  }
  double plausible = double(std::max<size_t>(2, word.size() / 3));
  return bestScore <= plausible ? best : std::string();
}

std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  std::string match = closestMatch(word, candidates);
  return match.empty() ? std::string() : " (did you mean '" + match + "'?)";
}

static std::string joinList(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

// Finds the line of the first occurrence of `token` in `text` (1-based), 0 when absent.
static size_t lineOf(const std::string& text, const std::string& token) {
  size_t at = token.empty() ? std::string::npos : text.find(token);
  if (at == std::string::npos) return 0;
  return size_t(std::count(text.begin(), text.begin() + long(at), '\n')) + 1;
}

std::string withoutExceptionTags(std::string message) {
  for (size_t at; (at = message.find("[json.exception.")) != std::string::npos;) {
    size_t close = message.find("] ", at);
    if (close == std::string::npos) break;
    message.erase(at, close + 2 - at);
  }
  return message;
}

bool readFile(const std::string& path, std::string& contents, std::string& error) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    error = "is a directory";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = std::strerror(errno);
    return false;
  }
  // A regular file is read straight into `contents` at its size: a scene file of hundreds of
  // megabytes then needs its size once in memory, not three times (stream buffer, copy).
  std::error_code sizeError;
  const bool regular = std::filesystem::is_regular_file(path, sizeError);
  const std::uintmax_t size = regular ? std::filesystem::file_size(path, sizeError) : 0;
  if (regular && !sizeError) {
    contents.resize(size_t(size));
    in.read(contents.data(), std::streamsize(size));
    if (in.bad() || size_t(in.gcount()) != size_t(size)) {
      error = "read error";
      return false;
    }
    if (in.peek() == std::ifstream::traits_type::eof()) return true;
    // The file grew while it was read: read the rest as a stream.
    in.clear();
  } else {
    contents.clear();
  }
  std::ostringstream rest;
  rest << in.rdbuf();
  if (in.bad()) {
    error = "read error";
    return false;
  }
  contents += rest.str();
  return true;
}

Json parseJsonStrict(const std::string& text, const std::string& origin) {
  // Tracks the path of the value being parsed so that duplicate keys can be reported.
  struct Frame {
    bool isArray = false;
    size_t index = 0;
    std::string key;
    std::set<std::string> keys;
  };
  std::vector<Frame> frames;
  auto pathTo = [&](const std::string& lastKey) {
    std::string path;
    for (size_t i = 0; i + 1 < frames.size(); ++i) {
      if (frames[i].isArray) path += "[" + std::to_string(frames[i].index) + "]";
      else path += (path.empty() ? "" : ".") + frames[i].key;
    }
    return path + (path.empty() ? "" : ".") + lastKey;
  };
  using Event = Json::parse_event_t;
  Json::parser_callback_t watchKeys = [&](int, Event event, Json& parsed) {
    switch (event) {
      case Event::object_start: frames.push_back(Frame{}); break;
      case Event::array_start: frames.push_back(Frame{true, 0, {}, {}}); break;
      case Event::key: {
        std::string key = parsed.get<std::string>();
        if (!frames.back().keys.insert(key).second)
          throwSceneError(origin, pathTo(key), "duplicate key");
        frames.back().key = key;
        break;
      }
      case Event::value:
        if (!frames.empty() && frames.back().isArray) ++frames.back().index;
        break;
      case Event::object_end:
      case Event::array_end:
        frames.pop_back();
        if (!frames.empty() && frames.back().isArray) ++frames.back().index;
        break;
    }
    return true;
  };
  try {
    return Json::parse(text, watchKeys);
  } catch (const Json::parse_error& e) {
    throwSceneError(origin, "", "malformed JSON: " + withoutExceptionTags(e.what()));
  } catch (const Json::exception& e) {
    // e.g. "number overflow parsing '1e999'": no position is given, so locate the token.
    std::string message = withoutExceptionTags(e.what());
    size_t quote = message.find('\'');
    size_t line = 0;
    if (quote != std::string::npos) {
      size_t end = message.find('\'', quote + 1);
      if (end != std::string::npos) line = lineOf(text, message.substr(quote + 1, end - quote - 1));
    }
    std::string where = line ? " at line " + std::to_string(line) : "";
    throwSceneError(origin, "", "malformed JSON" + where + ": " + message);
  }
}

bool Range::contains(double v) const {
  bool aboveLo = loInclusive ? v >= lo : v > lo;
  bool belowHi = hiInclusive ? v <= hi : v < hi;
  return aboveLo && belowHi;
}

std::string formatNumber(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.7g", v);
  return buffer;
}

std::string Range::describe() const {
  bool hasLo = lo > -1e299, hasHi = hi < 1e299;
  if (hasLo && hasHi) {
    return std::string("in ") + (loInclusive ? "[" : "(") + formatNumber(lo) + ", " + formatNumber(hi) +
           (hiInclusive ? "]" : ")");
  }
  if (hasLo) return std::string(loInclusive ? ">= " : "> ") + formatNumber(lo);
  if (hasHi) return std::string(hiInclusive ? "<= " : "< ") + formatNumber(hi);
  return "a finite number";
}

JsonLocation JsonLocation::child(const std::string& key) const {
  return {origin, path.empty() ? key : path + "." + key};
}

JsonLocation JsonLocation::item(size_t index) const {
  return {origin, path + "[" + std::to_string(index) + "]"};
}

static std::string typeOf(const Json& value) { return value.type_name(); }

double readNumber(const Json& value, const JsonLocation& at, Range range) {
  if (!value.is_number()) at.fail("expected a number, got " + typeOf(value));
  double v = value.get<double>();
  if (!std::isfinite(v)) at.fail("must be a finite number");
  if (std::fabs(v) > double(FLT_MAX)) at.fail("is too large for single precision (got " + formatNumber(v) + ")");
  if (!range.contains(v)) at.fail("must be " + range.describe() + " (got " + formatNumber(v) + ")");
  return v;
}

int64_t readInteger(const Json& value, const JsonLocation& at, int64_t lo, int64_t hi) {
  std::string allowed = "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (value.is_number_unsigned() && value.get<uint64_t>() > uint64_t(INT64_MAX))
    at.fail("must be an integer " + allowed);
  int64_t v = 0;
  if (value.is_number_integer()) {
    v = value.get<int64_t>();
  } else if (value.is_number_float()) {
    double d = value.get<double>();
    if (!std::isfinite(d) || d != std::floor(d)) at.fail("must be an integer (got " + formatNumber(d) + ")");
    if (d < double(lo) || d > double(hi)) at.fail("must be an integer " + allowed + " (got " + formatNumber(d) + ")");
    v = int64_t(d);
  } else {
    at.fail("expected an integer, got " + typeOf(value));
  }
  if (v < lo || v > hi) at.fail("must be an integer " + allowed + " (got " + std::to_string(v) + ")");
  return v;
}

template <int N>
static glm::vec<N, float> readVector(const Json& value, const JsonLocation& at, Range range) {
  if (!value.is_array() || value.size() != size_t(N))
    at.fail("expected an array of " + std::to_string(N) + " numbers");
  glm::vec<N, float> v;
  for (int i = 0; i < N; ++i) v[i] = float(readNumber(value[size_t(i)], at.item(size_t(i)), range));
  return v;
}

glm::vec3 readVec3(const Json& value, const JsonLocation& at, Range range) { return readVector<3>(value, at, range); }
glm::vec2 readVec2(const Json& value, const JsonLocation& at, Range range) { return readVector<2>(value, at, range); }

std::string readString(const Json& value, const JsonLocation& at) {
  if (!value.is_string()) at.fail("expected a string, got " + typeOf(value));
  return value.get<std::string>();
}

ObjectReader::ObjectReader(const Json& value, JsonLocation at) : object_(value), at_(std::move(at)) {
  if (!value.is_object()) {
    if (at_.path.empty()) at_.fail("the top level must be a JSON object, got " + typeOf(value));
    at_.fail("expected an object, got " + typeOf(value));
  }
}

void ObjectReader::fail(const std::string& key, const std::string& problem) const {
  locationOf(key).fail(problem);
}

bool ObjectReader::has(const std::string& key) {
  knownKeys_.insert(key);
  return object_.contains(key);
}

void ObjectReader::failOnMisspellingOf(const std::string& key) const {
  for (const auto& item : object_.items()) {
    if (knownKeys_.count(item.key()) || closestMatch(item.key(), {key}).empty()) continue;
    fail(item.key(), "unknown key (did you mean '" + key + "'?)");
  }
}

const Json& ObjectReader::required(const std::string& key) {
  if (has(key)) return object_.at(key);
  failOnMisspellingOf(key);  // a misspelling of the missing key is the likelier mistake
  fail(key, "missing required key");
}

const Json* ObjectReader::optional(const std::string& key) {
  return has(key) ? &object_.at(key) : nullptr;
}

double ObjectReader::number(const std::string& key, Range range) {
  return readNumber(required(key), locationOf(key), range);
}

double ObjectReader::number(const std::string& key, double fallback, Range range) {
  const Json* value = optional(key);
  return value ? readNumber(*value, locationOf(key), range) : fallback;
}

int64_t ObjectReader::integer(const std::string& key, int64_t lo, int64_t hi) {
  return readInteger(required(key), locationOf(key), lo, hi);
}

int64_t ObjectReader::integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) {
  const Json* value = optional(key);
  return value ? readInteger(*value, locationOf(key), lo, hi) : fallback;
}

glm::vec3 ObjectReader::vec3(const std::string& key, Range range) {
  return readVec3(required(key), locationOf(key), range);
}

glm::vec3 ObjectReader::vec3(const std::string& key, glm::vec3 fallback, Range range) {
  const Json* value = optional(key);
  return value ? readVec3(*value, locationOf(key), range) : fallback;
}

glm::vec3 ObjectReader::rgb(const std::string& key, float fallback, Range range) {
  const Json* value = optional(key);
  if (!value) return glm::vec3(fallback);
  if (value->is_array()) return readVec3(*value, locationOf(key), range);
  return glm::vec3(float(readNumber(*value, locationOf(key), range)));
}

glm::vec2 ObjectReader::vec2(const std::string& key, glm::vec2 fallback, Range range) {
  const Json* value = optional(key);
  return value ? readVec2(*value, locationOf(key), range) : fallback;
}

std::string ObjectReader::string(const std::string& key) { return readString(required(key), locationOf(key)); }

std::string ObjectReader::string(const std::string& key, const std::string& fallback) {
  const Json* value = optional(key);
  return value ? readString(*value, locationOf(key)) : fallback;
}

std::string ObjectReader::choice(const std::string& key, const std::vector<std::string>& options,
                                 const std::string& fallback) {
  const Json* value = optional(key);
  if (!value) return fallback;
  std::string chosen = readString(*value, locationOf(key));
  if (std::find(options.begin(), options.end(), chosen) == options.end())
    fail(key, "unknown value '" + chosen + "'" + didYouMean(chosen, options) + ", expected one of: " +
                  joinList(options));
  return chosen;
}

bool ObjectReader::boolean(const std::string& key, bool fallback) {
  const Json* value = optional(key);
  if (!value) return fallback;
  if (!value->is_boolean()) fail(key, "expected true or false, got " + typeOf(*value));
  return value->get<bool>();
}

void ObjectReader::forbid(const std::string& key, const std::string& reason) {
  if (has(key)) fail(key, reason);
}

void ObjectReader::finish() const {
  std::vector<std::string> known(knownKeys_.begin(), knownKeys_.end());
  for (const auto& item : object_.items()) {
    if (knownKeys_.count(item.key())) continue;
    std::string hint = didYouMean(item.key(), known);
    if (hint.empty()) hint = known.empty() ? " (no keys are allowed here)" : " (expected one of: " + joinList(known) + ")";
    fail(item.key(), "unknown key" + hint);
  }
}

}  // namespace vs
