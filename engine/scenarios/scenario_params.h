#pragma once
// The parameters of a scenario family: integer knobs with a default and an inclusive range. A family
// lists them in a fixed order; that order is the order they are written into a scene's "generator".
#include <string>
#include <utility>
#include <vector>

namespace dash {

struct ParamSpec {
  std::string name;
  int default_value = 0;
  int min = 0;
  int max = 0;
  bool even_only = false;  ///< e.g. shelf-wall robots: 2, 4, 6, ...
  std::string meaning;     ///< one line for `dashbench scenario --list`

  /// "2..32", or "2..8, even".
  std::string rangeText() const;
};

/// Resolved values, one per ParamSpec of the family, in the family's order.
class ScenarioParams {
 public:
  ScenarioParams() = default;
  explicit ScenarioParams(std::vector<std::pair<std::string, int>> values) : values_(std::move(values)) {}

  /// The value of `name`; a missing name is a bug in a generator (aborts).
  int get(const std::string& name) const;
  const std::vector<std::pair<std::string, int>>& values() const { return values_; }

 private:
  std::vector<std::pair<std::string, int>> values_;
};

/// Defaults overridden by `key=value` words. Throws InputError naming the key and its allowed range on
/// an unknown key, a value that is not an integer, or one out of range.
ScenarioParams resolveParams(const std::string& family, const std::vector<ParamSpec>& specs,
                             const std::vector<std::pair<std::string, std::string>>& overrides);

}  // namespace dash
