#pragma once
// JSON codec for dashbench.plan/1. Parsing checks the structure strictly (types, required fields,
// lengths, unit quaternions, non-negative times) and throws InputError with the path of the offending
// field, e.g. "robots.ur5e_0.points[3].q: expected 6 numbers, got 5". Whether the plan obeys the
// contract (time order, limits, collisions, ...) is the validator's job (plan_validator.h). Unknown
// fields are ignored: the contract lets writers add fields. Writing is deterministic: the same plan
// always gives byte-identical text.
#include <string>

#include "engine/plan/plan.h"
#include "engine/plan/plan_validator.h"

namespace dash {

/// Parses a plan. `source_name` prefixes error messages (a file name, or empty).
Plan parsePlan(const std::string& json_text, const std::string& source_name = "");
/// Reads and parses a plan file; throws InputError if it cannot be read or is malformed.
Plan loadPlan(const std::string& path);

/// Pretty-printed JSON (indent 1, fields in contract order, robots in Plan::robots order, events in
/// Plan::events order), ending with a newline.
std::string planToJson(const Plan& plan);
/// Writes planToJson(plan) to `path`; throws InputError if the file cannot be written.
void savePlan(const Plan& plan, const std::string& path);

/// A validation report as JSON (indent 1): {"valid", "samples", "problems": [{"kind", "t", "t_end",
/// "robot", "object", "other", "message"}]}, kinds named by problemKindName(). Ends with a newline.
std::string validationReportToJson(const ValidationReport& report);

}  // namespace dash
