#pragma once
// Private to server/http's .cpp files: nlohmann-json helpers for request bodies and SQL rows.
#include <nlohmann/json.hpp>
#include <string>

#include "engine/log/sqlite_util.h"

namespace httplib {
struct Request;
}

namespace dash::http {

using Json = nlohmann::json;

/// The request body as a JSON object; HttpError 400 with a clear message when it is empty, not
/// JSON, or not an object.
Json parseBodyObject(const httplib::Request& req);

Json toJson(const log::SqlValue& value);
/// {"columns": [...], "rows": [[...], ...], "truncated": bool}
Json rowsToJson(const log::SqlRows& rows);
/// Row `i` of `rows` as {"column": value, ...}.
Json rowObject(const log::SqlRows& rows, std::size_t i);

/// JSON text that may be stored in the database (params, settings, plans); null when empty or invalid.
Json parseStored(const std::string& text);

}  // namespace dash::http
