#pragma once
// Named planner parameters: every heuristic a planner adds beyond its paper is one of these, with its
// default, the value that turns it off (the paper's algorithm) and a one-line description, so that
// runs can switch extensions off one at a time (ablation) and a batch can sweep them. The CLI lists
// them (`dashbench plan --params`), sets them (`--set NAME=VALUE`, `--profile paper`), batch specs
// accept the same names in a planner's "settings", and a run stores its full effective set.
//
// Values are text: "true"/"false" for switches, decimal integers, decimal reals. Unknown names and
// bad values throw InputError naming the parameter.
#include <map>
#include <string>
#include <vector>

namespace dash {

enum class ParamType { kBool, kInt, kReal };

struct ParamInfo {
  std::string name;
  ParamType type = ParamType::kBool;
  std::string default_value;
  /// The value of the algorithm as published; empty for a parameter the paper has too (a budget),
  /// which `--profile paper` leaves alone.
  std::string paper_value;
  double min = 0.0, max = 0.0;  ///< numbers only, inclusive
  std::string description;
  /// Where it comes from: the paper's section ("Query (Motion-extended Hypergraph)") or "beyond the paper".
  std::string source;

  bool extension() const { return !paper_value.empty(); }
};

/// Name -> value text.
using ParamValues = std::map<std::string, std::string>;

/// The parameters of a planner ("lazy-dash", "dash"); InputError for another name.
const std::vector<ParamInfo>& plannerParameters(const std::string& planner);
/// Every parameter's effective value: the defaults with `overrides` applied (each checked).
ParamValues resolveParameters(const std::string& planner, const ParamValues& overrides);
/// The overrides a profile stands for: "paper" (every extension at its paper value) or "default" (none).
ParamValues profileOverrides(const std::string& planner, const std::string& profile);
/// "NAME=VALUE" split (InputError without '=').
std::pair<std::string, std::string> parseAssignment(const std::string& text);
/// The table `dashbench plan --params` prints.
std::string describeParameters(const std::string& planner);
/// The same as a Markdown table (parameter, default, paper value, source, what it does): docs/planners.md.
std::string parametersMarkdown(const std::string& planner);
/// {"name": value, ...} with booleans and numbers as JSON values, keys sorted.
std::string parametersJson(const ParamValues& values);

bool paramBool(const ParamValues& values, const std::string& name);
int paramInt(const ParamValues& values, const std::string& name);
double paramReal(const ParamValues& values, const std::string& name);

}  // namespace dash
