#pragma once
// Reading a JSON document field by field, where every error names the field's path
// ("robots[2].home[3]: expected a number, got string"). The one reader behind the scene, plan and robot
// model codecs, the batch spec and the dispatch messages; each supplies its own error (InputError by
// default, a SpecError for batch specs) through the error hook.
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "engine/core/check.h"

namespace dash {

/// What went wrong with a field, for callers that classify errors (the batch spec's error kinds);
/// kSyntax: the text is no JSON at all (json_parse.h).
enum class JsonErrorKind { kSyntax, kType, kMissing, kRange, kValue };

/// "path.key", or "key" at the root.
inline std::string jsonPathJoin(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

/// "path[i]"; built by appending (GCC 12 warns falsely on "[" + std::to_string(i) + "]").
inline std::string jsonPathIndex(const std::string& path, std::size_t i) {
  std::string out = path;
  out += '[';
  out += std::to_string(i);
  out += ']';
  return out;
}

/// Called with the error's kind, the field's full path and the message; must throw.
using JsonErrorHandler = std::function<void(JsonErrorKind, const std::string& path, const std::string& message)>;

/// Throws InputError("SOURCE: PATH: MESSAGE"); an empty path names the document itself (`root_name`).
inline JsonErrorHandler inputErrorHandler(const std::string& source, const std::string& root_name) {
  const std::string prefix = source.empty() ? "" : source + ": ";
  return [prefix, root_name](JsonErrorKind, const std::string& path, const std::string& message) {
    throw InputError(prefix + (path.empty() ? root_name : path) + ": " + message);
  };
}

/// Field-by-field reader over nlohmann::json or nlohmann::ordered_json.
template <class JsonT>
class JsonReader {
 public:
  /// Errors become InputError("SOURCE: PATH: MESSAGE").
  JsonReader(const std::string& source, const std::string& root_name)
      : on_error_(inputErrorHandler(source, root_name)) {}
  explicit JsonReader(JsonErrorHandler on_error) : on_error_(std::move(on_error)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& message,
                         JsonErrorKind kind = JsonErrorKind::kValue) const {
    on_error_(kind, path, message);
    throw InputError(path + ": " + message);  // a handler that returns is a bug; never reached otherwise
  }

  static std::string join(const std::string& path, const std::string& key) { return jsonPathJoin(path, key); }
  static std::string index(const std::string& path, std::size_t i) { return jsonPathIndex(path, i); }

  void requireObject(const JsonT& value, const std::string& path) const {
    if (!value.is_object()) fail(path, "expected an object" + got(value), JsonErrorKind::kType);
  }

  /// The value of `key` in `object` (whose path is `path`); fails if `object` is no object or lacks it.
  const JsonT& field(const JsonT& object, const std::string& path, const std::string& key) const {
    requireObject(object, path);
    const auto it = object.find(key);
    if (it == object.end()) fail(join(path, key), "missing field", JsonErrorKind::kMissing);
    return *it;
  }

  /// The value of `key`, or nullptr when `object` lacks it.
  const JsonT* optionalField(const JsonT& object, const std::string& path, const std::string& key) const {
    requireObject(object, path);
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  const JsonT& array(const JsonT& value, const std::string& path) const {
    if (!value.is_array()) fail(path, "expected an array" + got(value), JsonErrorKind::kType);
    return value;
  }

  /// A finite number.
  double number(const JsonT& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "expected a number" + got(value), JsonErrorKind::kType);
    const double x = value.template get<double>();
    if (!std::isfinite(x)) fail(path, "number is not finite", JsonErrorKind::kRange);
    return x;
  }

  /// An integer that fits in int64.
  std::int64_t integer(const JsonT& value, const std::string& path) const {
    if (!value.is_number_integer()) fail(path, "expected an integer" + got(value), JsonErrorKind::kType);
    if (value.is_number_unsigned() && value.template get<std::uint64_t>() >
                                          static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      fail(path, "integer too large", JsonErrorKind::kRange);
    }
    return value.template get<std::int64_t>();
  }

  std::string string(const JsonT& value, const std::string& path) const {
    if (!value.is_string()) fail(path, "expected a string" + got(value), JsonErrorKind::kType);
    return value.template get<std::string>();
  }

  std::string nonEmptyString(const JsonT& value, const std::string& path) const {
    std::string s = string(value, path);
    if (s.empty()) fail(path, "must not be empty");
    return s;
  }

  bool boolean(const JsonT& value, const std::string& path) const {
    if (!value.is_boolean()) fail(path, "expected true or false" + got(value), JsonErrorKind::kType);
    return value.template get<bool>();
  }

  /// An array of exactly `length` finite numbers.
  std::vector<double> numbers(const JsonT& value, const std::string& path, std::size_t length) const {
    array(value, path);
    if (value.size() != length) {
      fail(path, "expected " + std::to_string(length) + " numbers, got " + std::to_string(value.size()),
           JsonErrorKind::kValue);
    }
    std::vector<double> out;
    out.reserve(length);
    for (std::size_t i = 0; i < length; ++i) out.push_back(number(value[i], index(path, i)));
    return out;
  }

  /// numbers() of the field `key` of `parent`.
  std::vector<double> numbersAt(const JsonT& parent, const std::string& path, const std::string& key,
                                std::size_t length) const {
    return numbers(field(parent, path, key), join(path, key), length);
  }

  /// An array of strings.
  std::vector<std::string> strings(const JsonT& value, const std::string& path) const {
    array(value, path);
    std::vector<std::string> out;
    out.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) out.push_back(string(value[i], index(path, i)));
    return out;
  }

 private:
  /// ", got TYPE": the value's type, never its text (a hostile document may be deep or huge).
  static std::string got(const JsonT& value) { return std::string(", got ") + value.type_name(); }

  JsonErrorHandler on_error_;
};

}  // namespace dash
