#pragma once
// Small nlohmann-json helpers shared by the dispatch codecs (only .cpp files include this header).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "engine/core/json_reader.h"
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

/// The project's field reader (engine/core/json_reader.h): errors are InputError("PATH: MESSAGE").
inline const JsonReader<Json>& reader() {
  static const JsonReader<Json> r("", "message");
  return r;
}

inline const Json& field(const Json& j, const char* key, const std::string& path) { return reader().field(j, path, key); }

inline std::string str(const Json& j, const char* key, const std::string& path) {
  return reader().string(field(j, key, path), jsonPathJoin(path, key));
}

inline std::string strOr(const Json& j, const char* key, const std::string& fallback, const std::string& path) {
  return j.contains(key) ? str(j, key, path) : fallback;
}

inline double num(const Json& j, const char* key, const std::string& path) {
  return reader().number(field(j, key, path), jsonPathJoin(path, key));
}

inline double numOr(const Json& j, const char* key, double fallback, const std::string& path) {
  return j.contains(key) ? num(j, key, path) : fallback;
}

inline std::int64_t int64(const Json& j, const char* key, const std::string& path) {
  return reader().integer(field(j, key, path), jsonPathJoin(path, key));
}

inline bool boolOr(const Json& j, const char* key, bool fallback, const std::string& path) {
  return j.contains(key) ? reader().boolean(j[key], jsonPathJoin(path, key)) : fallback;
}

inline Json vec(const JointVector& v) {
  Json a = Json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

inline JointVector toVec(const Json& a, const std::string& path) {
  reader().array(a, path);
  if (a.size() > 6) reader().fail(path, "expected at most 6 numbers, got " + std::to_string(a.size()));
  JointVector v(static_cast<Eigen::Index>(a.size()));
  for (std::size_t i = 0; i < a.size(); ++i) v[static_cast<Eigen::Index>(i)] = reader().number(a[i], jsonPathIndex(path, i));
  return v;
}

inline std::vector<std::string> strings(const Json& a, const std::string& path) { return reader().strings(a, path); }

}  // namespace dash::dispatch::json_util
