#pragma once
// Command-line arguments of one subcommand: --name VALUE / --name=VALUE options, --flag switches,
// positional words, and key=value parameters. Unknown options are an InputError naming them.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace dash::cli {

struct ArgSpec {
  std::set<std::string> options;  ///< take a value: --out FILE
  std::set<std::string> flags;    ///< take none: --json
  std::set<std::string> repeated; ///< take a value, may be given several times: --set A=1 --set B=2
  bool key_values = false;        ///< accept key=value words as parameters
};

class Args {
 public:
  Args(const std::vector<std::string>& words, const ArgSpec& spec);

  bool has(const std::string& name) const;  ///< option given or flag set
  std::optional<std::string> get(const std::string& name) const;
  std::string get(const std::string& name, const std::string& fallback) const;
  std::string require(const std::string& name) const;  ///< throws InputError if missing
  double number(const std::string& name, double fallback) const;
  long long integer(const std::string& name, long long fallback) const;

  /// Every value of a repeated option, in order (empty if not given).
  std::vector<std::string> all(const std::string& name) const;
  const std::vector<std::string>& positional() const { return positional_; }
  const std::vector<std::pair<std::string, std::string>>& keyValues() const { return key_values_; }

 private:
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> repeated_;
  std::set<std::string> flags_;
  std::vector<std::string> positional_;
  std::vector<std::pair<std::string, std::string>> key_values_;
};

/// Parses "1,2,3" into numbers; throws InputError naming `what` on a bad entry.
std::vector<double> parseNumberList(const std::string& text, const std::string& what);

}  // namespace dash::cli
