#include "harness/pipeline/params.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace vs {

ParamSpec ParamSpec::integer(std::string name, int def, int min, int max, std::string description) {
  ParamSpec p;
  p.name = std::move(name);
  p.kind = Kind::Int;
  p.defaultValue = std::to_string(def);
  p.min = min;
  p.max = max;
  p.description = std::move(description);
  return p;
}

ParamSpec ParamSpec::real(std::string name, double def, double min, double max, std::string description) {
  ParamSpec p;
  p.name = std::move(name);
  p.kind = Kind::Float;
  std::ostringstream s;
  s << def;
  p.defaultValue = s.str();
  p.min = min;
  p.max = max;
  p.description = std::move(description);
  return p;
}

ParamSpec ParamSpec::flag(std::string name, bool def, std::string description) {
  ParamSpec p;
  p.name = std::move(name);
  p.kind = Kind::Bool;
  p.defaultValue = def ? "1" : "0";
  p.description = std::move(description);
  return p;
}

ParamSpec ParamSpec::choice(std::string name, std::string def, std::vector<std::string> choices,
                            std::string description) {
  ParamSpec p;
  p.name = std::move(name);
  p.kind = Kind::Choice;
  p.defaultValue = std::move(def);
  p.choices = std::move(choices);
  p.description = std::move(description);
  return p;
}

std::string ParamSpec::rangeText() const {
  std::ostringstream s;
  switch (kind) {
    case Kind::Int:
      s << int64_t(min) << ".." << int64_t(max) << (powerOfTwo ? " (power of two)" : "");
      break;
    case Kind::Float:
      s << min << ".." << max;
      break;
    case Kind::Bool:
      s << "0|1";
      break;
    case Kind::Choice:
      for (size_t i = 0; i < choices.size(); ++i) s << (i ? "|" : "") << choices[i];
      break;
  }
  return s.str();
}

static std::string normalise(const std::string& method, const ParamSpec& spec, const std::string& raw) {
  auto fail = [&](const std::string& why) {
    throw UsageError("method '" + method + "': " + spec.name + "=" + raw + ": " + why + " (expected " +
                     spec.rangeText() + ")");
  };
  switch (spec.kind) {
    case ParamSpec::Kind::Int: {
      errno = 0;
      char* end = nullptr;
      long long v = std::strtoll(raw.c_str(), &end, 10);
      if (raw.empty() || *end != '\0' || errno == ERANGE) fail("not an integer");
      if (v < spec.min || v > spec.max) fail("out of range");
      if (spec.powerOfTwo && (v <= 0 || (v & (v - 1)) != 0)) fail("not a power of two");
      return std::to_string(v);
    }
    case ParamSpec::Kind::Float: {
      errno = 0;
      char* end = nullptr;
      double v = std::strtod(raw.c_str(), &end);
      if (raw.empty() || *end != '\0' || errno == ERANGE) fail("not a number");
      if (!std::isfinite(v)) fail("not finite");
      if (v < spec.min || v > spec.max) fail("out of range");
      std::ostringstream s;
      s << v;
      return s.str();
    }
    case ParamSpec::Kind::Bool:
      if (raw == "1" || raw == "true" || raw == "on" || raw == "yes") return "1";
      if (raw == "0" || raw == "false" || raw == "off" || raw == "no") return "0";
      fail("not a boolean");
      break;
    case ParamSpec::Kind::Choice:
      for (const auto& c : spec.choices)
        if (c == raw) return raw;
      fail("not one of the choices");
      break;
  }
  return raw;
}

ParamValues ParamValues::parse(const std::string& method, const std::vector<ParamSpec>& specs,
                               const std::map<std::string, std::string>& given) {
  for (const auto& [key, value] : given) {
    bool known = false;
    for (const auto& s : specs) known = known || s.name == key;
    if (!known) {
      std::string names;
      for (const auto& s : specs) names += (names.empty() ? "" : ", ") + s.name;
      throw UsageError("method '" + method + "' has no parameter '" + key + "' (parameters: " + names + ")");
    }
  }
  ParamValues out;
  for (const auto& s : specs) {
    auto it = given.find(s.name);
    std::string value = normalise(method, s, it == given.end() ? s.defaultValue : it->second);
    out.values_[s.name] = value;
    out.ordered_.emplace_back(s.name, value);
  }
  return out;
}

static const std::string& lookup(const std::map<std::string, std::string>& m, const std::string& key) {
  auto it = m.find(key);
  if (it == m.end()) throw std::logic_error("parameter '" + key + "' was never declared");
  return it->second;
}

int ParamValues::getInt(const std::string& key) const { return std::stoi(read(key)); }
double ParamValues::getFloat(const std::string& key) const { return std::stod(read(key)); }
bool ParamValues::getBool(const std::string& key) const { return read(key) == "1"; }
const std::string& ParamValues::getString(const std::string& key) const { return read(key); }

const std::string& ParamValues::read(const std::string& key) const {
  const std::string& value = lookup(values_, key);
  reads_->insert(key);
  return value;
}

std::string ParamValues::canonical() const {
  std::string s;
  for (const auto& [k, v] : ordered_) s += (s.empty() ? "" : ":") + k + "=" + v;
  return s;
}

MethodSpec parseMethodSpec(const std::string& text) {
  MethodSpec spec;
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, ':')) parts.push_back(part);
  if (parts.empty() || parts[0].empty()) throw UsageError("empty method spec '" + text + "'");
  spec.method = parts[0];
  for (size_t i = 1; i < parts.size(); ++i) {
    auto eq = parts[i].find('=');
    if (eq == std::string::npos || eq == 0)
      throw UsageError("method spec '" + text + "': '" + parts[i] + "' is not key=value");
    std::string key = parts[i].substr(0, eq);
    if (spec.params.count(key)) throw UsageError("method spec '" + text + "': key '" + key + "' given twice");
    spec.params[key] = parts[i].substr(eq + 1);
  }
  return spec;
}

}  // namespace vs
