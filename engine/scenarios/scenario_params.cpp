#include "engine/scenarios/scenario_params.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>

#include "engine/core/check.h"

namespace dash {

std::string ParamSpec::rangeText() const {
  std::string text = std::to_string(min) + ".." + std::to_string(max);
  if (even_only) text += ", even";
  return text;
}

int ScenarioParams::get(const std::string& name) const {
  const auto it = std::find_if(values_.begin(), values_.end(), [&](const auto& v) { return v.first == name; });
  DASH_DEMAND_MSG(it != values_.end(), "scenario parameter '" + name + "' is not defined by this family");
  return it->second;
}

namespace {

/// Strict integer parse: optional sign, digits only, within int range.
bool parseInt(const std::string& text, int& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (errno != 0 || end != text.c_str() + text.size()) return false;
  if (v < -1000000000LL || v > 1000000000LL) return false;
  out = static_cast<int>(v);
  return true;
}

}  // namespace

ScenarioParams resolveParams(const std::string& family, const std::vector<ParamSpec>& specs,
                             const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::vector<std::pair<std::string, int>> values;
  for (const ParamSpec& s : specs) values.emplace_back(s.name, s.default_value);
  for (const auto& [key, text] : overrides) {
    const auto spec = std::find_if(specs.begin(), specs.end(), [&](const ParamSpec& s) { return s.name == key; });
    if (spec == specs.end()) {
      std::string known;
      for (const ParamSpec& s : specs) known += (known.empty() ? "" : ", ") + s.name + " (" + s.rangeText() + ")";
      throw InputError("unknown parameter '" + key + "' for scenario " + family + "; its parameters are: " + known);
    }
    int value = 0;
    const std::string where = "parameter " + key + " of scenario " + family;
    DASH_THROW_UNLESS(parseInt(text, value),
                      where + ": '" + text + "' is not an integer (allowed: " + spec->rangeText() + ")");
    DASH_THROW_UNLESS(value >= spec->min && value <= spec->max,
                      where + " = " + text + " is out of range (allowed: " + spec->rangeText() + ")");
    DASH_THROW_UNLESS(!spec->even_only || value % 2 == 0,
                      where + " = " + text + " must be even (allowed: " + spec->rangeText() + ")");
    const auto index = static_cast<std::size_t>(spec - specs.begin());
    values[index].second = value;
  }
  return ScenarioParams(std::move(values));
}

}  // namespace dash
