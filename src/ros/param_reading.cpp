#include "roar/ros/param_reading.h"

#include "roar/config/yaml_section.h"
#include "roar/ros/frames.h"

#include <ros/package.h>
#include <ros/param.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace roar::ros_bridge {

std::string readMapFrame(const ros::NodeHandle& nh) { return readString(nh, "map_frame", kMapFrame); }

namespace {

// Every parameter a reader asked for in this process, by full name: what refuseUnknownParameters knows.
std::set<std::string>& askedFor() {
  static std::set<std::string> names;
  return names;
}

std::string fullName(const ros::NodeHandle& nh, const std::string& name) { return nh.resolveName(name); }

// XmlRpc keeps ints and doubles apart; a YAML "3" for a double parameter is fine.
bool asDouble(const XmlRpc::XmlRpcValue& v, double* out) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    return *out = static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(v)), true;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    return *out = static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(v)), true;
  return false;
}

}  // namespace

double readDouble(const ros::NodeHandle& nh, const std::string& name, double fallback, double lo, double hi) {
  XmlRpc::XmlRpcValue v;
  markParameterKnown(nh, name);
  if (!nh.getParam(name, v)) return fallback;
  double value;
  if (!asDouble(v, &value)) throw ParamError("parameter " + fullName(nh, name) + " must be a number");
  if (!std::isfinite(value) || value < lo || value > hi) {
    throw ParamError("parameter " + fullName(nh, name) + " = " + std::to_string(value) + " must be in [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return value;
}

int readInt(const ros::NodeHandle& nh, const std::string& name, int fallback, int lo, int hi) {
  XmlRpc::XmlRpcValue v;
  markParameterKnown(nh, name);
  if (!nh.getParam(name, v)) return fallback;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeInt)
    throw ParamError("parameter " + fullName(nh, name) + " must be an integer");
  const int value = static_cast<int>(v);
  if (value < lo || value > hi) {
    throw ParamError("parameter " + fullName(nh, name) + " = " + std::to_string(value) + " must be in [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return value;
}

bool readBool(const ros::NodeHandle& nh, const std::string& name, bool fallback) {
  XmlRpc::XmlRpcValue v;
  markParameterKnown(nh, name);
  if (!nh.getParam(name, v)) return fallback;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean)
    throw ParamError("parameter " + fullName(nh, name) + " must be true or false");
  return static_cast<bool>(v);
}

std::string readString(const ros::NodeHandle& nh, const std::string& name, const std::string& fallback) {
  XmlRpc::XmlRpcValue v;
  markParameterKnown(nh, name);
  if (!nh.getParam(name, v)) return fallback;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString)
    throw ParamError("parameter " + fullName(nh, name) + " must be a string");
  return static_cast<std::string>(v);
}

std::string readChoice(const ros::NodeHandle& nh, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& choices) {
  const std::string value = readString(nh, name, fallback);
  std::string listed;
  for (const auto& c : choices) {
    if (c == value) return value;
    listed += (listed.empty() ? "" : ", ") + c;
  }
  throw ParamError("parameter " + fullName(nh, name) + " = '" + value + "' must be one of: " + listed);
}

std::vector<std::string> readStringList(const ros::NodeHandle& nh, const std::string& name,
                                        const std::vector<std::string>& fallback) {
  XmlRpc::XmlRpcValue v;
  markParameterKnown(nh, name);
  if (!nh.getParam(name, v)) return fallback;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString) return {static_cast<std::string>(v)};
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray)
    throw ParamError("parameter " + fullName(nh, name) + " must be a list of strings");
  std::vector<std::string> out;
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() != XmlRpc::XmlRpcValue::TypeString) {
      throw ParamError("parameter " + fullName(nh, name) + "[" + std::to_string(i) + "] must be a string");
    }
    out.push_back(static_cast<std::string>(v[i]));
  }
  return out;
}

void markParameterKnown(const ros::NodeHandle& nh, const std::string& name) { askedFor().insert(nh.resolveName(name)); }

void refuseUnknownParameters(const ros::NodeHandle& private_nh) {
  std::vector<std::string> names;
  if (!ros::param::getParamNames(names)) return;  // no master to ask: the readers already failed
  const std::string ns = private_nh.getNamespace() + "/";
  std::vector<std::string> known;
  for (const auto& k : askedFor()) {
    if (k.compare(0, ns.size(), ns) == 0) known.push_back(k.substr(ns.size()));
  }
  std::string unknown;
  for (const auto& name : names) {
    if (name.compare(0, ns.size(), ns) != 0) continue;
    const std::string own = name.substr(ns.size());
    // A structured parameter (a dictionary) is listed leaf by leaf.
    const bool asked = std::any_of(known.begin(), known.end(), [&](const std::string& k) {
      return own == k || own.compare(0, k.size() + 1, k + "/") == 0;
    });
    if (asked) continue;
    const std::string near = config::nearestKey(own, known);
    unknown += (unknown.empty() ? "" : "; ") + name + (near.empty() ? "" : " (did you mean '" + ns + near + "'?)");
  }
  if (!unknown.empty()) {
    throw ParamError("unknown parameter" + std::string(unknown.find(';') == std::string::npos ? "" : "s") + " " +
                     unknown + ": " + private_nh.getNamespace() + " has no such parameter (doc/ros_api.md lists them)");
  }
}

config::PackageLayout packageLayout() { return {ros::package::getPath("roar_ros")}; }

}  // namespace roar::ros_bridge
