#include "server/cli/args.h"

#include <cmath>

#include "engine/core/check.h"
#include "engine/core/text_split.h"

namespace dash::cli {

Args::Args(const std::vector<std::string>& words, const ArgSpec& spec) {
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& w = words[i];
    if (w.rfind("--", 0) == 0 && w.size() > 2) {
      std::string name = w.substr(2);
      std::optional<std::string> inline_value;
      if (auto eq = name.find('='); eq != std::string::npos) {
        inline_value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      if (spec.flags.count(name) != 0) {
        DASH_THROW_UNLESS(!inline_value, "option --" + name + " takes no value");
        flags_.insert(name);
      } else if (spec.repeated.count(name) != 0) {
        if (inline_value) {
          repeated_[name].push_back(*inline_value);
        } else {
          DASH_THROW_UNLESS(i + 1 < words.size(), "option --" + name + " needs a value");
          repeated_[name].push_back(words[++i]);
        }
        DASH_THROW_UNLESS(repeated_[name].size() <= 1000, "option --" + name + " given too many times");
      } else if (spec.options.count(name) != 0) {
        if (inline_value) {
          values_[name] = *inline_value;
        } else {
          DASH_THROW_UNLESS(i + 1 < words.size(), "option --" + name + " needs a value");
          values_[name] = words[++i];
        }
      } else {
        throw InputError("unknown option --" + name + " (see --help)");
      }
    } else if (spec.key_values && w.find('=') != std::string::npos && w.front() != '=') {
      const auto eq = w.find('=');
      key_values_.emplace_back(w.substr(0, eq), w.substr(eq + 1));
    } else {
      positional_.push_back(w);
    }
  }
}

bool Args::has(const std::string& name) const {
  return flags_.count(name) != 0 || values_.count(name) != 0 || repeated_.count(name) != 0;
}

std::vector<std::string> Args::all(const std::string& name) const {
  auto it = repeated_.find(name);
  return it == repeated_.end() ? std::vector<std::string>{} : it->second;
}

std::optional<std::string> Args::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  return get(name).value_or(fallback);
}

std::string Args::require(const std::string& name) const {
  auto v = get(name);
  DASH_THROW_UNLESS(v.has_value(), "missing required option --" + name);
  return *v;
}

static double parseDouble(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError(what + ": '" + text + "' is not a number");
  }
  DASH_THROW_UNLESS(used == text.size(), what + ": '" + text + "' is not a number");
  DASH_THROW_UNLESS(std::isfinite(value), what + ": '" + text + "' is not finite");
  return value;
}

double Args::number(const std::string& name, double fallback) const {
  auto v = get(name);
  return v ? parseDouble(*v, "--" + name) : fallback;
}

long long Args::integer(const std::string& name, long long fallback) const {
  auto v = get(name);
  if (!v) return fallback;
  const double d = parseDouble(*v, "--" + name);
  DASH_THROW_UNLESS(d == std::floor(d), "--" + name + ": '" + *v + "' is not an integer");
  return static_cast<long long>(d);
}

std::vector<double> parseNumberList(const std::string& text, const std::string& what) {
  // Empty items kept: "1,,3" and "1,2," are refused as not numbers rather than read as shorter lists.
  std::vector<double> out;
  for (const std::string& item : splitList(text, ',', EmptyItems::kKeep)) out.push_back(parseDouble(item, what));
  return out;
}

}  // namespace dash::cli
