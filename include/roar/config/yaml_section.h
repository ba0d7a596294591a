#pragma once
// The one strict reader of roar_ros's YAML files (sensor sets, RL options, ...): a section reads the keys
// it knows and refuses any other, naming the file, the key and the nearest known key ("did you mean"),
// so a misspelt `imag_width:` is an error instead of a silent default. Errors are thrown as the caller's
// exception type, so every module keeps its own.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace roar::config {

// The candidate nearest to `key` (edit distance at most a third of its length, at least 2), or "".
std::string nearestKey(const std::string& key, const std::vector<std::string>& candidates);

template <class Error>
class YamlSection {
 public:
  // `path`: where the mapping sits in the file ("" for the top), `source`: the file (or request) for errors.
  YamlSection(const YAML::Node& node, std::string path, std::string source)
      : node_(node), path_(std::move(path)), source_(std::move(source)) {
    if (node_ && !node_.IsNull() && !node_.IsMap())
      fail(path_.empty() ? "the file" : path_, "must be a mapping of keys");
    checkKeys();
  }

  bool has(const std::string& key) const { return node_ && node_.IsMap() && node_[key]; }

  // An optional key: leaves *out as it is when the key is absent; returns whether it was there.
  template <class T>
  bool read(const std::string& key, T* out) {
    known_.insert(key);
    if (!has(key)) return false;
    try {
      *out = node_[key].template as<T>();
    } catch (const YAML::Exception&) {
      fail(where(key), "is not a " + typeName<T>());
    }
    if constexpr (std::is_same_v<T, double>) {
      if (!std::isfinite(*out)) fail(where(key), "is not a finite number");
    }
    if constexpr (std::is_same_v<T, std::vector<double>>) {
      for (double v : *out) {
        if (!std::isfinite(v)) fail(where(key), "holds a number that is not finite");
      }
    }
    return true;
  }

  template <class T>
  T require(const std::string& key) {
    T out{};
    if (!read(key, &out)) fail(where(key), "is missing" + misspeltAs(key));
    return out;
  }

  // A key some other code reads (its node is handed over as is).
  YAML::Node raw(const std::string& key) {
    known_.insert(key);
    return has(key) ? node_[key] : YAML::Node();
  }

  YamlSection child(const std::string& key) {
    known_.insert(key);
    return YamlSection(has(key) ? node_[key] : YAML::Node(), where(key), source_);
  }

  // Refuses every key no read(), require(), raw() or child() asked for.
  void finish() const {
    if (!node_ || !node_.IsMap()) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.as<std::string>();
      if (known_.count(key)) continue;
      const std::vector<std::string> known(known_.begin(), known_.end());
      const std::string near = nearestKey(key, known);
      std::string keys;
      for (const auto& k : known) keys += (keys.empty() ? "" : ", ") + k;
      fail(where(key),
           "is not a known key" + (near.empty() ? "" : " (did you mean '" + near + "'?)") + "; known: " + keys);
    }
  }

  // " (is 'x' a misspelling of it?)" when the mapping has an unrequested key near `key`, else "".
  std::string misspeltAs(const std::string& key) const {
    if (!node_ || !node_.IsMap()) return "";
    for (const auto& entry : node_) {
      const std::string other = entry.first.as<std::string>();
      if (!known_.count(other) && nearestKey(other, {key}) == key) return " (is '" + other + "' a misspelling of it?)";
    }
    return "";
  }

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(source_ + ": " + field + ": " + what);
  }
  std::string where(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& source() const { return source_; }

 private:
  template <class T>
  static std::string typeName() {
    if constexpr (std::is_same_v<T, bool>) return "boolean";
    if constexpr (std::is_integral_v<T>) return "whole number";
    if constexpr (std::is_same_v<T, double>) return "number";
    if constexpr (std::is_same_v<T, std::string>) return "string";
    if constexpr (std::is_same_v<T, std::vector<std::string>>) return "list of strings";
    return "list of numbers";
  }

  // yaml-cpp keeps a repeated key and answers with its first value: a second `friction:` would be silently
  // ignored, so a key given twice is refused (config_test).
  void checkKeys() const {
    if (!node_ || !node_.IsMap()) return;
    std::set<std::string> seen;
    for (const auto& entry : node_) {
      if (!entry.first.IsScalar()) fail(path_.empty() ? "the file" : path_, "has a key that is not a plain name");
      if (!seen.insert(entry.first.Scalar()).second) fail(where(entry.first.Scalar()), "is given twice");
    }
  }

  YAML::Node node_;
  std::string path_;
  std::string source_;
  std::set<std::string> known_;
};

}  // namespace roar::config
