// ResultsDb::mergeFrom: runs from another results file, keyed by their global uuid, and its dispatch
// records, keyed by their id.
#include <sqlite3.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "engine/core/check.h"
#include "engine/log/arena_views.h"
#include "engine/log/results_db.h"
#include "engine/log/results_db_impl.h"
#include "engine/log/results_schema.h"

namespace dash::log {
namespace {

// Tables keyed by run_id whose rows follow their run.
constexpr const char* kRunChildTables[] = {"dash_repr_events", "dash_constraints", "dash_expansions", "dash_phases",
                                           "dash_counters", "dash_progress",    "dash_run_tags"};

std::vector<std::string> columnsOf(sqlite3* db, const std::string& schema, const std::string& table) {
  std::vector<std::string> columns;
  sql::Statement st(db, "SELECT name FROM pragma_table_info(?, ?) ORDER BY cid");
  st.bind(1, table).bind(2, schema);
  while (st.step()) columns.push_back(st.columnText(0));
  return columns;
}

std::string joined(const std::vector<std::string>& names, const std::string& prefix) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + prefix + sql::quoteIdentifier(n);
  return out;
}

std::vector<std::string> without(std::vector<std::string> names, std::initializer_list<const char*> drop) {
  std::erase_if(names, [&](const std::string& n) {
    for (const char* d : drop) {
      if (n == d) return true;
    }
    return false;
  });
  return names;
}

// "file:" URI for ATTACH, read-only; '%', '?' and '#' are escaped.
std::string readOnlyUri(const std::string& path) {
  std::string uri = "file:";
  for (char c : path) {
    if (c == '%' || c == '?' || c == '#') {
      char hex[4];
      std::snprintf(hex, sizeof(hex), "%%%02X", static_cast<unsigned char>(c));
      uri += hex;
    } else {
      uri += c;
    }
  }
  return uri + "?mode=ro";
}

// An input at an older schema version is migrated in a temporary copy; the input stays untouched.
class MigratedCopy {
 public:
  explicit MigratedCopy(const std::string& path) {
    sql::Connection source = sql::open(path, SQLITE_OPEN_READONLY);
    const int version = readSchemaVersion(source.get());
    if (version > kSchemaVersion) {
      throw SchemaError(path + ": database schema version " + std::to_string(version) +
                        " is newer than this dashbench (" + std::to_string(kSchemaVersion) + "); upgrade dashbench");
    }
    if (version == kSchemaVersion) {
      path_ = path;
      return;
    }
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/dashbench-merge-XXXXXX";
    const int fd = mkstemp(pattern.data());
    if (fd < 0) throw DbError("cannot create a temporary file for migrating " + path);
    close(fd);
    temporary_ = pattern;
    path_ = pattern;
    sql::Connection copy = sql::open(path_, SQLITE_OPEN_READWRITE);
    sqlite3_backup* backup = sqlite3_backup_init(copy.get(), "main", source.get(), "main");
    if (backup == nullptr) sql::fail(copy.get(), "cannot copy " + path);
    sqlite3_backup_step(backup, -1);
    if (sqlite3_backup_finish(backup) != SQLITE_OK) sql::fail(copy.get(), "cannot copy " + path);
    migrateSchema(copy.get(), path);
  }
  ~MigratedCopy() {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
  }
  MigratedCopy(const MigratedCopy&) = delete;
  MigratedCopy& operator=(const MigratedCopy&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string temporary_;
};

// Dispatch records follow their id (see MergeReport). A record of the output is the same dispatch
// when what was asked is the same (created, client, who, scene, planner, time scale) and its id is
// the input's, or the input's plus the suffix an earlier merge gave it: a later state of it (ended)
// replaces an active one, else the output's copy stays. Runs are referred to by uuid, so run_uuid
// needs no mapping.
void mergeDispatches(sqlite3* db, MergeReport& report) {
  const std::string same_request =
      "m.created IS s.created AND m.client IS s.client AND m.requested_by IS s.requested_by AND m.scene IS s.scene "
      "AND m.planner IS s.planner AND m.time_scale IS s.time_scale";
  sql::exec(db, "CREATE TEMP TABLE merge_dispatch AS SELECT s.id AS old_id, s.ended IS NOT NULL AS finished, "
                "COALESCE((SELECT m.id FROM main.dash_dispatches m WHERE m.id = s.id AND " + same_request + "), "
                "(SELECT m.id FROM main.dash_dispatches m WHERE length(m.id) = length(s.id) + 9 AND "
                "substr(m.id, 1, length(s.id) + 1) = s.id || '-' AND " + same_request + " LIMIT 1)) AS same_id, "
                "NULL AS action, NULL AS new_id FROM src.dash_dispatches s");
  sql::exec(db,
            "UPDATE temp.merge_dispatch SET action = CASE "
            "WHEN same_id IS NOT NULL THEN CASE WHEN finished AND (SELECT ended FROM main.dash_dispatches "
            "WHERE id = same_id) IS NULL THEN 'replace' ELSE 'skip' END "
            "WHEN old_id IN (SELECT id FROM main.dash_dispatches) THEN 'other' ELSE 'new' END");
  sql::exec(db, "UPDATE temp.merge_dispatch SET new_id = CASE action WHEN 'replace' THEN same_id ELSE old_id END "
                "WHERE action <> 'other'");
  // An id the output holds for another dispatch (two servers, before ids carried a random tag): a
  // fresh suffix until it is free.
  while (sql::selectInt(db, "SELECT COUNT(*) FROM temp.merge_dispatch WHERE new_id IS NULL AND action = 'other'") > 0) {
    sql::exec(db,
              "UPDATE temp.merge_dispatch SET new_id = old_id || '-' || lower(hex(randomblob(4))) "
              "WHERE new_id IS NULL AND action = 'other'");
    sql::exec(db,
              "UPDATE temp.merge_dispatch SET new_id = NULL WHERE action = 'other' AND new_id IN "
              "(SELECT id FROM main.dash_dispatches UNION ALL SELECT old_id FROM temp.merge_dispatch)");
  }
  auto count = [&](const char* actions) {
    return sql::selectInt(db, std::string("SELECT COUNT(*) FROM temp.merge_dispatch WHERE action IN (") + actions + ")");
  };
  report.dispatches_added = count("'new', 'other'");
  report.dispatches_replaced = count("'replace'");
  report.dispatches_skipped = count("'skip'");
  sql::exec(db, "DELETE FROM main.dash_dispatch_arms WHERE dispatch_id IN "
                "(SELECT new_id FROM temp.merge_dispatch WHERE action = 'replace')");
  sql::exec(db, "DELETE FROM main.dash_dispatches WHERE id IN "
                "(SELECT new_id FROM temp.merge_dispatch WHERE action = 'replace')");
  const std::string copied = " JOIN temp.merge_dispatch md ON md.old_id = s.";
  const std::string wanted = " WHERE md.action IN ('new', 'other', 'replace')";
  const auto dispatch_columns = without(columnsOf(db, "main", "dash_dispatches"), {"id"});
  sql::exec(db, "INSERT INTO main.dash_dispatches (id, " + joined(dispatch_columns, "") + ") SELECT md.new_id, " +
                    joined(dispatch_columns, "s.") + " FROM src.dash_dispatches s" + copied + "id" + wanted +
                    " ORDER BY s.created, s.id");
  const auto arm_columns = without(columnsOf(db, "main", "dash_dispatch_arms"), {"dispatch_id"});
  sql::exec(db, "INSERT INTO main.dash_dispatch_arms (dispatch_id, " + joined(arm_columns, "") +
                    ") SELECT md.new_id, " + joined(arm_columns, "s.") + " FROM src.dash_dispatch_arms s" + copied +
                    "dispatch_id" + wanted);
  sql::exec(db, "DROP TABLE temp.merge_dispatch");
}

}  // namespace

MergeReport ResultsDb::mergeFrom(const std::string& other_path) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(std::filesystem::exists(other_path), "no database file at " + other_path);
  DASH_THROW_UNLESS(!std::filesystem::equivalent(other_path, m.path), "cannot merge " + other_path + " into itself");
  MigratedCopy input(other_path);
  {
    sql::Connection probe = sql::open(input.path(), SQLITE_OPEN_READONLY);
    checkSchemaReadable(probe.get(), other_path);
  }
  std::lock_guard lock(m.mutex);
  sqlite3* db = m.db.get();
  sql::Statement attach(db, "ATTACH DATABASE ? AS src");
  attach.bind(1, readOnlyUri(input.path())).run();
  MergeReport report;
  try {
    sql::exec(db, "BEGIN IMMEDIATE");
    const auto batch_columns = columnsOf(db, "main", "dash_batches");
    sql::exec(db, "INSERT OR IGNORE INTO main.dash_batches (" + joined(batch_columns, "") + ") SELECT " +
                      joined(batch_columns, "") + " FROM src.dash_batches");
    sql::exec(db, "INSERT OR IGNORE INTO main.dash_experiments (family, params, version) "
                  "SELECT family, params, version FROM src.dash_experiments ORDER BY id");
    sql::exec(db, "INSERT OR IGNORE INTO main.dash_planner_configs (name, planner, settings) "
                  "SELECT name, planner, settings FROM src.dash_planner_configs ORDER BY id");

    // Runs this file still has as 'running' but the input has finished: the input's copy wins.
    sql::exec(db, "CREATE TEMP TABLE merge_replace AS SELECT m.id AS id, m.uuid AS uuid FROM main.dash_runs m "
                  "JOIN src.dash_runs s ON s.uuid = m.uuid WHERE m.status = 'running' AND s.status <> 'running'");
    for (const auto& [uuid, run] : m.active) {  // never replace a run this process is recording
      sql::Statement keep(db, "DELETE FROM temp.merge_replace WHERE uuid = ?");
      keep.bind(1, uuid).run();
    }
    report.replaced = sql::selectInt(db, "SELECT COUNT(*) FROM temp.merge_replace");
    for (const char* table : kRunChildTables) {
      sql::exec(db, std::string("DELETE FROM main.") + table + " WHERE run_id IN (SELECT id FROM temp.merge_replace)");
    }
    sql::exec(db, "DELETE FROM main.dash_runs WHERE id IN (SELECT id FROM temp.merge_replace)");

    sql::exec(db, "CREATE TEMP TABLE merge_new AS SELECT s.id AS old_id, s.uuid AS uuid FROM src.dash_runs s "
                  "WHERE s.uuid NOT IN (SELECT uuid FROM main.dash_runs) ORDER BY s.id");
    const std::int64_t incoming = sql::selectInt(db, "SELECT COUNT(*) FROM temp.merge_new");
    report.added = incoming - report.replaced;
    report.skipped = sql::selectInt(db, "SELECT COUNT(*) FROM src.dash_runs") - incoming;

    const auto run_columns = without(columnsOf(db, "main", "dash_runs"), {"id", "experiment_id", "planner_config_id"});
    sql::exec(db,
              "INSERT INTO main.dash_runs (" + joined(run_columns, "") + ", experiment_id, planner_config_id) SELECT " +
                  joined(run_columns, "s.") +
                  ", (SELECT me.id FROM main.dash_experiments me JOIN src.dash_experiments se ON me.family = se.family "
                  "AND me.params = se.params AND me.version = se.version WHERE se.id = s.experiment_id), "
                  "(SELECT mp.id FROM main.dash_planner_configs mp JOIN src.dash_planner_configs sp ON mp.name = sp.name "
                  "AND mp.planner = sp.planner AND mp.settings = sp.settings WHERE sp.id = s.planner_config_id) "
                  "FROM src.dash_runs s JOIN temp.merge_new n ON n.old_id = s.id ORDER BY s.id");
    sql::exec(db, "CREATE TEMP TABLE merge_map AS SELECT n.old_id AS old_id, m.id AS new_id FROM temp.merge_new n "
                  "JOIN main.dash_runs m ON m.uuid = n.uuid");
    for (const char* table : kRunChildTables) {
      const auto columns = without(columnsOf(db, "main", table), {"run_id"});
      sql::exec(db, std::string("INSERT INTO main.") + table + " (run_id, " + joined(columns, "") +
                        ") SELECT mm.new_id, " + joined(columns, "s.") + " FROM src." + table +
                        " s JOIN temp.merge_map mm ON s.run_id = mm.old_id");
    }
    sql::exec(db, "DROP TABLE temp.merge_replace; DROP TABLE temp.merge_new; DROP TABLE temp.merge_map");
    mergeDispatches(db, report);

    sql::Statement names(db, "SELECT DISTINCT j.key FROM main.dash_experiments e, json_each(e.params) j");
    while (names.step()) m.parameter_names.insert(names.columnText(0));
    dash::log::refreshArenaViews(db);
    sql::exec(db, "COMMIT");
  } catch (...) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_exec(db, "DETACH DATABASE src", nullptr, nullptr, nullptr);
    throw;
  }
  sql::exec(db, "DETACH DATABASE src");
  return report;
}

}  // namespace dash::log
