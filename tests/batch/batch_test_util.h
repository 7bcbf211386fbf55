#pragma once
// Shared by the batch tests: a temporary folder, the dashbench binary, and database helpers.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/log/results_db.h"
#include "server/batch/batch_runner.h"
#include "server/batch/batch_spec.h"
#include "tests/common/temp_dir.h"

namespace dash::batch::testing {

using test::TempDir;

inline std::string binary() { return DASHBENCH_BINARY; }

/// Runner options for tests: the dashbench binary (the test binary has no run-one), short grace.
inline RunnerOptions testOptions(int workers) {
  RunnerOptions o;
  o.workers = workers;
  o.executable = binary();
  o.kill_grace = 1.0;
  o.time_slack = 0.25;
  return o;
}

inline BatchSpec specOf(const std::string& text) {
  return parseBatchSpec(text, "test spec", SpecOptions{.check_combinations = false});
}

/// A spec of sorting scenes (robots=4, the object counts given) x seeds x the planners given (JSON list).
inline std::string sortingSpec(const std::string& objects, const std::string& seeds, const std::string& planners,
                               double time_limit = 20) {
  return R"({"name":"test","time_limit":)" + std::to_string(time_limit) +
         R"(,"memory_limit":2048,"scenarios":[{"family":"sorting","params":{"robots":4,"objects":)" + objects +
         R"(}}],"planners":)" + planners + R"(,"seeds":)" + seeds + "}";
}

inline const char* kTaskOnly = R"({"name":"lazy-dash","settings":{"task_only":true},"label":"lazy-task"})";

/// The first column of the first row of a SELECT, as an integer.
inline std::int64_t scalar(const log::ResultsDb& db, const std::string& sql,
                           const std::vector<log::SqlValue>& params = {}) {
  const log::SqlRows rows = db.select(sql, params);
  if (rows.rows.empty() || std::holds_alternative<std::monostate>(rows.rows[0][0])) return 0;
  return std::get<std::int64_t>(rows.rows[0][0]);
}

}  // namespace dash::batch::testing
