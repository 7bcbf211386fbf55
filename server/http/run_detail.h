#pragma once
// One run, for the run detail page: its row (every RunTable column), parameters and settings, phase
// breakdown (totals and per iteration), event counts, latest counters, tags and note; its events
// (paged, one kind or all in time order); the timeline the page draws (representation sizes over
// time, constraints with the conflict that caused each, task space expansions, phase intervals);
// and its plan. Unknown uuids are HttpError 404.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dash::http {

/// What the scene regeneration needs from a run (scene_cache.h).
struct RunScenario {
  std::string family;
  std::vector<std::pair<std::string, int>> params;  ///< as stored (any order)
  std::uint64_t seed = 0;
  std::string scene_name;  ///< the scene the run planned, if recorded
};

class RunDetail {
 public:
  explicit RunDetail(std::string db_path) : db_path_(std::move(db_path)) {}

  std::string runJson(const std::string& uuid) const;
  /// `type`: "all" (every type, in the order recorded: seq), "representation", "constraint", "task_space_expansion",
  /// "phase" or "counter". {"total", "offset", "limit", "events": [{seq, t, iteration, type, what, id, detail}]}
  std::string eventsJson(const std::string& uuid, const std::string& type, std::int64_t offset,
                         std::int64_t limit) const;
  /// {"progress": {"columns", "rows"}, "constraints": [...], "expansions": [...], "phases": [...],
  ///  "truncated": {...}}; at most `max_items` of each list (progress is thinned evenly).
  std::string timelineJson(const std::string& uuid, std::int64_t max_items) const;
  /// The stored dashbench.plan/1 text; nullopt when the run has none.
  std::optional<std::string> planText(const std::string& uuid) const;
  RunScenario scenario(const std::string& uuid) const;

  /// Tags and notes (the run must exist): HttpError 404 otherwise, InputError for a bad tag.
  void editTags(const std::string& uuid, const std::vector<std::string>& add,
                const std::vector<std::string>& remove) const;
  void setNote(const std::string& uuid, const std::string& note) const;
  /// {"uuid", "tags": [...], "note"}
  std::string annotationsJson(const std::string& uuid) const;

 private:
  std::int64_t runId(const std::string& uuid) const;

  std::string db_path_;
};

}  // namespace dash::http
