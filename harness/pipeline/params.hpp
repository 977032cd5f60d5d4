// Method parameters: declarations, spec strings `name:key=value:key=value`, validation.
#pragma once
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace vs {

// Bad user input (unknown method/key, out-of-range value). what() is one line.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ParamSpec {
  enum class Kind { Int, Float, Bool, Choice };
  std::string name;
  Kind kind = Kind::Int;
  std::string defaultValue;
  double min = 0, max = 0;           // Int and Float, inclusive
  std::vector<std::string> choices;  // Choice
  std::string description;
  bool powerOfTwo = false;           // Int values must be powers of two
  // The value changes how the image is computed (speed, memory, order of work), never the image;
  // the conformance test holds both ways (tests/conformance_tests.cpp).
  bool speedOnly = false;

  static ParamSpec integer(std::string name, int def, int min, int max, std::string description);
  static ParamSpec real(std::string name, double def, double min, double max, std::string description);
  static ParamSpec flag(std::string name, bool def, std::string description);
  static ParamSpec choice(std::string name, std::string def, std::vector<std::string> choices, std::string description);
  ParamSpec& pow2() {
    powerOfTwo = true;
    return *this;
  }
  ParamSpec& sameImage() {
    speedOnly = true;
    return *this;
  }
  std::string rangeText() const;  // "16..8192 (power of two)", "0|1", "a|b|c"
};

// Validated values for every declared parameter (defaults filled in).
class ParamValues {
 public:
  ParamValues() = default;
  // Throws UsageError naming the method and key for unknown keys, malformed or out-of-range values.
  static ParamValues parse(const std::string& method, const std::vector<ParamSpec>& specs,
                           const std::map<std::string, std::string>& given);
  int getInt(const std::string& key) const;
  double getFloat(const std::string& key) const;
  bool getBool(const std::string& key) const;
  const std::string& getString(const std::string& key) const;
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  // "key=value:key=value" over every parameter in declaration order (defaults included): stable
  // across runs, so it keys result rows and caches.
  std::string canonical() const;
  const std::vector<std::pair<std::string, std::string>>& items() const { return ordered_; }
  // The keys read through get*() so far, by this object or any copy of it (copies share the log):
  // the conformance test checks that a method reads every parameter it declares.
  const std::set<std::string>& keysRead() const { return *reads_; }

 private:
  const std::string& read(const std::string& key) const;
  std::map<std::string, std::string> values_;
  std::vector<std::pair<std::string, std::string>> ordered_;
  std::shared_ptr<std::set<std::string>> reads_ = std::make_shared<std::set<std::string>>();
};

struct MethodSpec {
  std::string method;
  std::map<std::string, std::string> params;
};
// Splits "name:key=value:key=value"; throws UsageError for malformed text or repeated keys.
MethodSpec parseMethodSpec(const std::string& text);

}  // namespace vs
