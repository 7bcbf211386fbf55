#include "server/http/run_detail.h"

#include <algorithm>

#include "engine/log/results_db.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/run_table.h"

namespace dash::http {

namespace {

constexpr std::size_t kMaxTagLength = 64;
constexpr std::size_t kMaxNoteLength = 10000;
constexpr std::size_t kMaxTagsPerRequest = 32;

Json rowsAsObjects(const log::SqlRows& rows) {
  Json out = Json::array();
  for (std::size_t i = 0; i < rows.rows.size(); ++i) out.push_back(rowObject(rows, i));
  return out;
}

std::int64_t intOf(const log::SqlValue& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  if (const auto* d = std::get_if<double>(&v)) return static_cast<std::int64_t>(*d);
  return 0;
}

void checkTag(const std::string& tag) {
  DASH_THROW_UNLESS(!tag.empty() && tag.size() <= kMaxTagLength,
                    "tag: must have 1 to " + std::to_string(kMaxTagLength) + " characters");
  for (unsigned char ch : tag) {
    DASH_THROW_UNLESS(ch >= 0x20 && ch != 0x7f && ch != ',', "tag '" + tag + "': no commas or control characters");
  }
}

/// The table behind each event type of the dash_timeline view (arena_views.cpp). Each has PRIMARY
/// KEY (run_id, seq), and seq numbers a run's events of every type in the order they were recorded,
/// so a page of events is a merge of index-ordered reads that stop after offset + limit keys: the
/// limit bounds the work (issue 40: limit=1 sorted all 36,860 events of a run, like limit=5000).
struct EventSource {
  const char* type;
  const char* table;
};
constexpr EventSource kEventSources[] = {{"representation", "dash_repr_events"},
                                         {"constraint", "dash_constraints"},
                                         {"task_space_expansion", "dash_expansions"},
                                         {"phase", "dash_phases"},
                                         {"counter", "dash_counters"}};

}  // namespace

std::int64_t RunDetail::runId(const std::string& uuid) const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const log::SqlRows rows = db.select("SELECT id FROM dash_runs WHERE uuid = ?", {uuid});
  if (rows.rows.empty()) throw HttpError(404, "no run " + uuid);
  return intOf(rows.rows[0][0]);
}

std::string RunDetail::runJson(const std::string& uuid) const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const RunTable table(db);
  const log::SqlRows row = db.select("SELECT " + table.selectList() +
                                         ", r.params AS _params, r.planner_settings AS _settings, r.note AS _note " +
                                         "FROM " + RunTable::fromClause() + " WHERE r.uuid = ?",
                                     {uuid});
  if (row.rows.empty()) throw HttpError(404, "no run " + uuid);
  Json run = rowObject(row, 0);
  const Json params = parseStored(run["_params"].is_string() ? run["_params"].get<std::string>() : "");
  const Json settings = parseStored(run["_settings"].is_string() ? run["_settings"].get<std::string>() : "");
  const Json note = run["_note"];
  run.erase("_params");
  run.erase("_settings");
  run.erase("_note");
  const std::int64_t id = run["id"].get<std::int64_t>();
  const std::vector<log::SqlValue> key = {id};

  Json phases = Json::object();
  for (const char* p : {"task_construction", "task_query", "task_conflict_detection", "motion_construction",
                        "motion_query", "conflict_resolution", "validation", "other"}) {
    phases[p] = run["time_" + std::string(p)];
  }
  const log::SqlRows counts = db.select(
      "SELECT (SELECT count(*) FROM dash_events WHERE run_id = ?1), (SELECT count(*) FROM dash_constraints WHERE "
      "run_id = ?1),"
      " (SELECT count(*) FROM dash_expansions WHERE run_id = ?1), (SELECT count(*) FROM dash_phases WHERE run_id = ?1),"
      " (SELECT count(*) FROM dash_counters WHERE run_id = ?1), (SELECT count(*) FROM dash_progress WHERE run_id = ?1)",
      key);
  Json event_counts = Json::object();
  const char* names[] = {"representation", "constraint", "task_space_expansion", "phase", "counter", "progress"};
  for (std::size_t i = 0; i < 6; ++i) event_counts[names[i]] = intOf(counts.rows[0][i]);

  const log::SqlRows counters = db.select(
      "SELECT c.name, c.value FROM dash_counters c WHERE c.run_id = ?1 AND c.seq = "
      "(SELECT max(seq) FROM dash_counters WHERE run_id = ?1 AND name = c.name) ORDER BY c.name",
      key);
  Json counter_json = Json::object();
  for (const auto& r : counters.rows) counter_json[std::get<std::string>(r[0])] = toJson(r[1]);

  const log::SqlRows per_iteration = db.select(
      "SELECT iteration, phase, sum(duration) AS seconds, count(*) AS count FROM dash_phases WHERE run_id = ? "
      "GROUP BY iteration, phase ORDER BY iteration, phase LIMIT 5000",
      key);
  const log::SqlRows constraint_kinds = db.select(
      "SELECT kind, action, count(*) AS count FROM dash_constraints WHERE run_id = ? GROUP BY kind, action ORDER BY "
      "kind",
      key);
  const log::SqlRows tags = db.select("SELECT tag FROM dash_run_tags WHERE run_id = ? ORDER BY tag", key);
  Json tag_list = Json::array();
  for (const auto& r : tags.rows) tag_list.push_back(toJson(r[0]));

  return jsonText(Json{{"run", run},
                       {"params", params},
                       {"settings", settings},
                       {"phases", phases},
                       {"phase_iterations", rowsAsObjects(per_iteration)},
                       {"event_counts", event_counts},
                       {"counters", counter_json},
                       {"constraints", rowsAsObjects(constraint_kinds)},
                       {"tags", tag_list},
                       {"note", note.is_null() ? Json("") : note}});
}

std::string RunDetail::eventsJson(const std::string& uuid, const std::string& type, std::int64_t offset,
                                  std::int64_t limit) const {
  const bool known = std::any_of(std::begin(kEventSources), std::end(kEventSources),
                                 [&](const EventSource& s) { return type == s.type; });
  if (type != "all" && !known) {
    throw HttpError(400, "type: '" + type +
                             "' is not one of all, representation, constraint, task_space_expansion, "
                             "phase, counter");
  }
  const std::int64_t id = runId(uuid);
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const std::int64_t wanted = offset > INT64_MAX - limit ? INT64_MAX : offset + limit;
  std::int64_t total = 0;
  std::vector<std::int64_t> seqs;
  for (const EventSource& s : kEventSources) {
    if (type != "all" && type != s.type) continue;
    const std::string table = s.table;
    total += intOf(db.select("SELECT count(*) FROM " + table + " WHERE run_id = ?", {id}).rows[0][0]);
    for (const auto& row :
         db.select("SELECT seq FROM " + table + " WHERE run_id = ? ORDER BY seq LIMIT ?", {id, wanted}).rows)
      seqs.push_back(intOf(row[0]));
  }
  std::sort(seqs.begin(), seqs.end());
  Json events = Json::array();
  if (static_cast<std::int64_t>(seqs.size()) > offset) {
    const auto first = seqs.begin() + offset;
    const auto last = seqs.end() - first > limit ? first + limit : seqs.end();
    std::string marks;
    std::vector<log::SqlValue> params = {id};
    for (auto it = first; it != last; ++it) {
      marks += marks.empty() ? "?" : ",?";
      params.emplace_back(*it);
    }
    events =
        rowsAsObjects(db.select("SELECT seq, t, iteration, type, what, id, detail FROM dash_timeline WHERE run_id = ? "
                                "AND seq IN (" +
                                    marks + ") ORDER BY seq",
                                params));
  }
  return jsonText(Json{{"total", total}, {"offset", offset}, {"limit", limit}, {"type", type}, {"events", events}});
}

std::string RunDetail::timelineJson(const std::string& uuid, std::int64_t max_items) const {
  const std::int64_t id = runId(uuid);
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const std::vector<log::SqlValue> key = {id};
  log::SqlRows progress = db.select(
      "SELECT t, iteration, task_vertices, task_hyperarcs, task_extended_vertices, task_extended_hyperarcs,"
      " motion_vertices, motion_hyperarcs, motion_extended_vertices, motion_extended_hyperarcs, roadmap_vertices,"
      " roadmap_edges, constraints, collision_checks, progress_phase, progress_done, progress_total, progress_rate,"
      " progress_current FROM dash_progress WHERE run_id = ? ORDER BY t",
      key);
  const std::size_t n = progress.rows.size();
  const bool thinned = static_cast<std::int64_t>(n) > max_items;
  if (thinned) {
    // Evenly spaced snapshots, always keeping the last (the final sizes).
    std::vector<std::vector<log::SqlValue>> kept;
    const double step = static_cast<double>(n - 1) / static_cast<double>(max_items - 1);
    for (std::int64_t i = 0; i < max_items; ++i) {
      kept.push_back(progress.rows[static_cast<std::size_t>(static_cast<double>(i) * step + 0.5)]);
    }
    progress.rows = std::move(kept);
  }
  const std::vector<log::SqlValue> limited = {id, max_items + 1};
  auto listOf = [&](const std::string& sql, bool& truncated) {
    log::SqlRows rows = db.select(sql, limited);
    truncated = static_cast<std::int64_t>(rows.rows.size()) > max_items;
    if (truncated) rows.rows.pop_back();
    return rowsAsObjects(rows);
  };
  bool c_trunc = false, e_trunc = false, p_trunc = false;
  Json constraints = listOf(
      "SELECT seq, t, iteration, kind, action, constraint_id AS id, content, vertices, conflict FROM dash_constraints "
      "WHERE run_id = ? ORDER BY t, seq LIMIT ?",
      c_trunc);
  Json expansions = listOf(
      "SELECT seq, t, iteration, object_id, object_label, added, reason FROM dash_expansions WHERE run_id = ? "
      "ORDER BY t, seq LIMIT ?",
      e_trunc);
  Json phases = listOf(
      "SELECT seq, iteration, phase, t_start, t_end, duration FROM dash_phases WHERE run_id = ? ORDER BY t_start, seq "
      "LIMIT ?",
      p_trunc);
  const log::SqlRows added = db.select(
      "SELECT iteration, layer, kind, sum(change = 'added') AS added, sum(change = 'removed') AS removed, min(t) AS "
      "t_first,"
      " max(t) AS t_last FROM dash_events WHERE run_id = ? GROUP BY iteration, layer, kind ORDER BY iteration, layer, "
      "kind "
      "LIMIT 5000",
      key);
  return jsonText(Json{
      {"progress", rowsToJson(progress)},
      {"constraints", std::move(constraints)},
      {"expansions", std::move(expansions)},
      {"phases", std::move(phases)},
      {"additions", rowsAsObjects(added)},
      {"truncated", {{"progress", thinned}, {"constraints", c_trunc}, {"expansions", e_trunc}, {"phases", p_trunc}}}});
}

std::optional<std::string> RunDetail::planText(const std::string& uuid) const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const log::SqlRows rows = db.select("SELECT plan FROM dash_runs WHERE uuid = ?", {uuid});
  if (rows.rows.empty()) throw HttpError(404, "no run " + uuid);
  if (!std::holds_alternative<std::string>(rows.rows[0][0])) return std::nullopt;
  return std::get<std::string>(rows.rows[0][0]);
}

RunScenario RunDetail::scenario(const std::string& uuid) const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const log::SqlRows rows = db.select("SELECT family, params, seed, scene FROM dash_runs WHERE uuid = ?", {uuid});
  if (rows.rows.empty()) throw HttpError(404, "no run " + uuid);
  RunScenario s;
  s.family = std::get<std::string>(rows.rows[0][0]);
  const Json params = parseStored(std::get<std::string>(rows.rows[0][1]));
  if (params.is_object()) {
    for (const auto& [name, value] : params.items()) {
      if (value.is_number_integer()) s.params.emplace_back(name, value.get<int>());
    }
  }
  s.seed = static_cast<std::uint64_t>(intOf(rows.rows[0][2]));
  if (const auto* name = std::get_if<std::string>(&rows.rows[0][3])) s.scene_name = *name;
  return s;
}

void RunDetail::editTags(const std::string& uuid, const std::vector<std::string>& add,
                         const std::vector<std::string>& remove) const {
  DASH_THROW_UNLESS(add.size() + remove.size() <= kMaxTagsPerRequest,
                    "at most " + std::to_string(kMaxTagsPerRequest) + " tags per request");
  for (const std::string& t : add) checkTag(t);
  runId(uuid);
  log::ResultsDb db(db_path_);
  for (const std::string& t : add) db.addTag(uuid, t);
  for (const std::string& t : remove) db.removeTag(uuid, t);
}

void RunDetail::setNote(const std::string& uuid, const std::string& note) const {
  DASH_THROW_UNLESS(note.size() <= kMaxNoteLength, "note: longer than " + std::to_string(kMaxNoteLength) + " bytes");
  runId(uuid);
  log::ResultsDb db(db_path_);
  db.setNote(uuid, note);
}

std::string RunDetail::annotationsJson(const std::string& uuid) const {
  const std::int64_t id = runId(uuid);
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const log::SqlRows tags = db.select("SELECT tag FROM dash_run_tags WHERE run_id = ? ORDER BY tag", {id});
  const log::SqlRows note = db.select("SELECT note FROM dash_runs WHERE id = ?", {id});
  Json list = Json::array();
  for (const auto& r : tags.rows) list.push_back(toJson(r[0]));
  const Json n = toJson(note.rows[0][0]);
  return jsonText(Json{{"uuid", uuid}, {"tags", list}, {"note", n.is_null() ? Json("") : n}});
}

}  // namespace dash::http
