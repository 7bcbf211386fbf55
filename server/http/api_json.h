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

/// Compact JSON text. Invalid UTF-8 (from a path, a query parameter or a database cell) becomes
/// U+FFFD instead of an exception (which was a 500).
std::string jsonText(const Json& j);

/// The request body as a JSON object; HttpError 400 with a clear message when it is empty, not
/// JSON (numbers out of range included), nested deeper than kMaxJsonDepth, or not an object.
Json parseBodyObject(const httplib::Request& req);

/// An integer member of a request body within [min, max]; HttpError 400 naming `key` otherwise.
/// (get<int>() would wrap 2^32 + 1 to 1.)
std::int64_t intMember(const Json& body, const std::string& key, std::int64_t min, std::int64_t max);

Json toJson(const log::SqlValue& value);
/// {"columns": [...], "rows": [[...], ...], "truncated": bool}
Json rowsToJson(const log::SqlRows& rows);
/// Row `i` of `rows` as {"column": value, ...}.
Json rowObject(const log::SqlRows& rows, std::size_t i);

/// JSON text that may be stored in the database (params, settings, plans); null when empty or invalid.
Json parseStored(const std::string& text);

}  // namespace dash::http
