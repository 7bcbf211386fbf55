#pragma once
// Small nlohmann-json helpers shared by the dispatch codecs (only .cpp files include this header).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "engine/robots/joint_vector.h"

namespace dash::dispatch::json_util {

using Json = nlohmann::json;

inline Json parseObject(const std::string& text, const std::string& what) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {  // parse_error, and out_of_range for numbers such as 1e400
    throw InputError(what + ": not JSON (" + e.what() + ")");
  }
  DASH_THROW_UNLESS(j.is_object(), what + ": expected a JSON object");
  return j;
}

inline const Json& field(const Json& j, const char* key, const std::string& path) {
  auto it = j.find(key);
  DASH_THROW_UNLESS(it != j.end(), path + "." + key + ": missing");
  return *it;
}

inline std::string str(const Json& j, const char* key, const std::string& path) {
  const Json& v = field(j, key, path);
  DASH_THROW_UNLESS(v.is_string(), path + "." + key + ": expected a string");
  return v.get<std::string>();
}

inline std::string strOr(const Json& j, const char* key, const std::string& fallback, const std::string& path) {
  return j.contains(key) ? str(j, key, path) : fallback;
}

inline double num(const Json& j, const char* key, const std::string& path) {
  const Json& v = field(j, key, path);
  DASH_THROW_UNLESS(v.is_number(), path + "." + key + ": expected a number");
  return v.get<double>();
}

inline double numOr(const Json& j, const char* key, double fallback, const std::string& path) {
  return j.contains(key) ? num(j, key, path) : fallback;
}

inline std::int64_t int64(const Json& j, const char* key, const std::string& path) {
  const Json& v = field(j, key, path);
  DASH_THROW_UNLESS(v.is_number_integer(), path + "." + key + ": expected an integer");
  return v.get<std::int64_t>();
}

inline bool boolOr(const Json& j, const char* key, bool fallback, const std::string& path) {
  if (!j.contains(key)) return fallback;
  const Json& v = j[key];
  DASH_THROW_UNLESS(v.is_boolean(), path + "." + key + ": expected true or false");
  return v.get<bool>();
}

inline Json vec(const JointVector& v) {
  Json a = Json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

inline JointVector toVec(const Json& a, const std::string& path) {
  DASH_THROW_UNLESS(a.is_array() && a.size() <= 6, path + ": expected at most 6 numbers");
  JointVector v(static_cast<Eigen::Index>(a.size()));
  for (std::size_t i = 0; i < a.size(); ++i) {
    DASH_THROW_UNLESS(a[i].is_number(), path + "[" + std::to_string(i) + "]: expected a number");
    v[static_cast<Eigen::Index>(i)] = a[i].get<double>();
  }
  return v;
}

inline std::vector<std::string> strings(const Json& a, const std::string& path) {
  DASH_THROW_UNLESS(a.is_array(), path + ": expected an array of strings");
  std::vector<std::string> out;
  for (const Json& s : a) {
    DASH_THROW_UNLESS(s.is_string(), path + ": expected an array of strings");
    out.push_back(s.get<std::string>());
  }
  return out;
}

}  // namespace dash::dispatch::json_util
