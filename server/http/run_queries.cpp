#include "server/http/run_queries.h"

#include "engine/log/db_query.h"
#include "engine/log/results_db.h"
#include "server/http/api_json.h"
#include "server/http/run_filter.h"
#include "server/http/run_table.h"

namespace dash::http {

namespace {

SqlCondition whereOf(const RunListRequest& request, const RunTable& table) {
  SqlCondition where = parseRunFilter(request.filter, table);
  if (!request.batch_id.empty()) where.andWith("r.batch_id = ?", {request.batch_id});
  if (!request.uuids.empty()) {
    std::string in;
    std::vector<log::SqlValue> values;
    for (const std::string& u : request.uuids) {
      in += in.empty() ? "?" : ", ?";
      values.emplace_back(u);
    }
    where.andWith("r.uuid IN (" + in + ")", std::move(values));
  }
  return where;
}

std::string orderBy(const RunListRequest& request, const RunTable& table) {
  const RunColumn* col = table.find(request.sort);
  DASH_THROW_UNLESS(col != nullptr, "sort: unknown column '" + request.sort + "'");
  // NULLs last either way, then a stable tie-break on the row id.
  const std::string dir = request.descending ? " DESC" : " ASC";
  return " ORDER BY (" + col->sql + ") IS NULL, " + col->sql + dir + ", r.id" + dir;
}

}  // namespace

std::string RunQueries::listJson(const RunListRequest& request) const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const RunTable table(db);
  const SqlCondition where = whereOf(request, table);
  const std::string where_sql = where.sql.empty() ? "" : " WHERE " + where.sql;
  const log::SqlRows count =
      db.select(std::string("SELECT count(*) FROM ") + RunTable::fromClause() + where_sql, where.params);
  std::vector<log::SqlValue> params = where.params;
  params.emplace_back(request.limit);
  params.emplace_back(request.offset);
  const log::SqlRows rows = db.select("SELECT " + table.selectList() + " FROM " + RunTable::fromClause() + where_sql +
                                          orderBy(request, table) + " LIMIT ? OFFSET ?",
                                      params);
  Json runs = Json::array();
  for (std::size_t i = 0; i < rows.rows.size(); ++i) runs.push_back(rowObject(rows, i));
  return jsonText(Json{{"total", toJson(count.rows.at(0).at(0))},
                       {"offset", request.offset},
                       {"limit", request.limit},
                       {"sort", request.sort},
                       {"order", request.descending ? "desc" : "asc"},
                       {"runs", std::move(runs)}});
}

std::string RunQueries::csv(const RunListRequest& request, std::int64_t max_rows) const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const RunTable table(db);
  const SqlCondition where = whereOf(request, table);
  std::vector<log::SqlValue> params = where.params;
  params.emplace_back(max_rows);
  const log::SqlRows rows =
      db.select("SELECT " + table.selectList(request.columns) + " FROM " + RunTable::fromClause() +
                    (where.sql.empty() ? "" : " WHERE " + where.sql) + orderBy(request, table) + " LIMIT ?",
                params);
  return log::formatRows(rows, log::OutputFormat::Csv);
}

std::string RunQueries::columnsJson() const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  return RunTable(db).columnsJson();
}

}  // namespace dash::http
