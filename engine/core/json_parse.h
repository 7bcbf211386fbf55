#pragma once
// The step before a JsonReader: a document's text parsed into JSON, every failure of the JSON
// library a clean error of the reader's kind, never an exception of its own.
#include <string>

#include "engine/core/json_reader.h"

namespace dash {

/// `text` parsed as JSON. Any exception of the JSON library, a syntax error as much as a number too
/// large for a double (1e400: out_of_range, not parse_error), goes to `reader`'s error hook as a
/// kSyntax error on the whole document: "SOURCE: ROOT: invalid JSON: [json.exception...] ...".
template <class JsonT>
JsonT parseJsonText(const JsonReader<JsonT>& reader, const std::string& text) {
  try {
    return JsonT::parse(text);
  } catch (const typename JsonT::exception& e) {
    reader.fail("", std::string("invalid JSON: ") + e.what(), JsonErrorKind::kSyntax);
  }
}

}  // namespace dash
