#include "server/http/run_filter.h"

#include <cctype>
#include <cstdlib>

#include "engine/core/check.h"

namespace dash::http {

namespace {

struct Token {
  enum Kind { kWord, kString, kOperator, kOpen, kClose, kEnd } kind = kEnd;
  std::string text;
  std::size_t pos = 0;
};

class Lexer {
 public:
  explicit Lexer(const std::string& text) : s_(text) {}

  Token next() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])) != 0) ++i_;
    Token t;
    t.pos = i_;
    if (i_ >= s_.size()) return t;
    const char ch = s_[i_];
    if (ch == '"' || ch == '\'') {
      t.kind = Token::kString;
      ++i_;
      while (i_ < s_.size() && s_[i_] != ch) t.text += s_[i_++];
      DASH_THROW_UNLESS(i_ < s_.size(),
                        "filter: the quote at position " + std::to_string(t.pos + 1) + " is not closed");
      ++i_;
      return t;
    }
    if (ch == '(' || ch == ')') {
      t.kind = ch == '(' ? Token::kOpen : Token::kClose;
      t.text = std::string(1, ch);
      ++i_;
      return t;
    }
    static const char* const kOps[] = {"!=", "<>", "<=", ">=", "==", "!~", "=", "<", ">", "~"};
    for (const char* op : kOps) {
      const std::string o(op);
      if (s_.compare(i_, o.size(), o) == 0) {
        t.kind = Token::kOperator;
        t.text = o == "<>" ? "!=" : o == "==" ? "=" : o;
        i_ += o.size();
        return t;
      }
    }
    t.kind = Token::kWord;
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])) == 0 &&
           std::string("=!<>~\"'()").find(s_[i_]) == std::string::npos) {
      t.text += s_[i_++];
    }
    return t;
  }

 private:
  const std::string& s_;
  std::size_t i_ = 0;
};

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

bool parseNumber(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

std::string at(const Token& t) { return " (at position " + std::to_string(t.pos + 1) + ")"; }

std::string likePattern(const std::string& value) {
  std::string out = "%";
  for (char ch : value) {
    if (ch == '%' || ch == '_' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "%";
}

std::string knownFields(const RunTable& table) {
  std::string out = "tag";
  for (const RunColumn& c : table.columns()) out += ", " + c.name;
  return out;
}

SqlCondition clause(const Token& field, const Token& op, const Token& value, const RunTable& table) {
  SqlCondition c;
  const std::string& o = op.text;
  if (lower(field.text) == "tag" || lower(field.text) == "tags") {
    if (o == "=" || o == "!=") {
      c.sql = std::string(o == "=" ? "" : "NOT ") +
              "EXISTS (SELECT 1 FROM dash_run_tags t WHERE t.run_id = r.id AND t.tag = ?)";
      c.params.emplace_back(value.text);
    } else if (o == "~" || o == "!~") {
      c.sql = std::string(o == "~" ? "" : "NOT ") +
              "EXISTS (SELECT 1 FROM dash_run_tags t WHERE t.run_id = r.id AND t.tag LIKE ? ESCAPE '\\')";
      c.params.emplace_back(likePattern(value.text));
    } else {
      throw InputError("filter: tag takes =, !=, ~ or !~" + at(op));
    }
    return c;
  }
  const RunColumn* col = table.find(field.text);
  if (col == nullptr) col = table.find(lower(field.text));
  if (col == nullptr)
    throw InputError("filter: unknown field '" + field.text + "'" + at(field) + "; fields: " + knownFields(table));
  if (o == "~" || o == "!~") {
    c.sql = "COALESCE(CAST(" + col->sql + " AS TEXT), '') " + (o == "~" ? "" : "NOT ") + "LIKE ? ESCAPE '\\'";
    c.params.emplace_back(likePattern(value.text));
    return c;
  }
  const std::string sql_op = o == "!=" ? "IS NOT" : o == "=" ? "IS" : o;
  if (col->type == ColumnType::kText) {
    c.sql = col->sql + " " + sql_op + " ?";
    c.params.emplace_back(value.text);
    return c;
  }
  double number = 0.0;
  if (value.kind == Token::kWord && (lower(value.text) == "null" || lower(value.text) == "none")) {
    DASH_THROW_UNLESS(o == "=" || o == "!=", "filter: null compares only with = or !=" + at(op));
    c.sql = col->sql + (o == "=" ? " IS NULL" : " IS NOT NULL");
    return c;
  }
  if (!parseNumber(value.text, number)) {
    throw InputError("filter: " + field.text + " is a number but '" + value.text + "' is not" + at(value));
  }
  c.sql = col->sql + " " + sql_op + " ?";
  c.params.emplace_back(number);
  return c;
}

}  // namespace

void SqlCondition::andWith(const SqlCondition& other) {
  if (other.sql.empty()) return;
  sql = sql.empty() ? other.sql : "(" + sql + ") AND (" + other.sql + ")";
  params.insert(params.end(), other.params.begin(), other.params.end());
}

void SqlCondition::andWith(const std::string& condition, std::vector<log::SqlValue> values) {
  andWith(SqlCondition{.sql = condition, .params = std::move(values)});
}

namespace {

constexpr int kMaxFilterDepth = 16;    // nested parentheses: a filter is typed by people
constexpr int kMaxFilterClauses = 64;  // FIELD OP VALUE clauses (about 100 overflowed SQLite's parser)

/// expression := conjunction ("or" conjunction)*; conjunction := factor ("and" factor)*;
/// factor := "(" expression ")" | FIELD OP VALUE. "and" binds tighter than "or".
class FilterParser {
 public:
  FilterParser(const std::string& text, const RunTable& table) : lex_(text), table_(table) { t_ = lex_.next(); }

  SqlCondition parse() {
    if (t_.kind == Token::kEnd) return {};
    SqlCondition out = expression(0);
    if (t_.kind == Token::kClose) throw InputError("filter: ')' without '('" + at(t_));
    if (t_.kind != Token::kEnd) throw InputError("filter: expected 'and' or 'or' between clauses" + at(t_));
    return out;
  }

 private:
  static bool isWord(const Token& t, const char* word, const char* symbol) {
    return t.kind == Token::kWord && (lower(t.text) == word || t.text == symbol);
  }

  // A chain of clauses is one flat list ("(a) OR (b) OR (c)"), not nested pairs: SQLite's parser
  // then needs no deeper stack for 64 clauses than for 2.
  SqlCondition expression(int depth) { return chain(depth, "or", "||", " OR ", &FilterParser::conjunction); }
  SqlCondition conjunction(int depth) { return chain(depth, "and", "&&", " AND ", &FilterParser::factor); }

  SqlCondition chain(int depth, const char* word, const char* symbol, const char* sql_op,
                     SqlCondition (FilterParser::*item)(int)) {
    SqlCondition out = (this->*item)(depth);
    if (!isWord(t_, word, symbol)) return out;
    out.sql = "(" + out.sql + ")";
    while (isWord(t_, word, symbol)) {
      t_ = lex_.next();
      const SqlCondition rhs = (this->*item)(depth);
      out.sql += std::string(sql_op) + "(" + rhs.sql + ")";
      out.params.insert(out.params.end(), rhs.params.begin(), rhs.params.end());
    }
    return out;
  }

  SqlCondition factor(int depth) {
    if (t_.kind == Token::kOpen) {
      if (depth >= kMaxFilterDepth) throw InputError("filter: parentheses nested deeper than 16" + at(t_));
      t_ = lex_.next();
      SqlCondition inner = expression(depth + 1);
      if (t_.kind != Token::kClose) throw InputError("filter: expected ')'" + at(t_));
      t_ = lex_.next();
      return inner;
    }
    if (t_.kind != Token::kWord) throw InputError("filter: expected a field name" + at(t_));
    const Token field = t_;
    const Token op = lex_.next();
    if (op.kind != Token::kOperator) {
      throw InputError("filter: expected an operator (= != < <= > >= ~ !~) after '" + field.text + "'" + at(op));
    }
    const Token value = lex_.next();
    if (value.kind != Token::kWord && value.kind != Token::kString) {
      throw InputError("filter: expected a value after '" + field.text + " " + op.text + "'" + at(value));
    }
    t_ = lex_.next();
    if (++clauses_ > kMaxFilterClauses) {
      throw InputError("filter: more than " + std::to_string(kMaxFilterClauses) + " clauses" + at(field));
    }
    return clause(field, op, value, table_);
  }

  Lexer lex_;
  const RunTable& table_;
  Token t_;
  int clauses_ = 0;
};

}  // namespace

SqlCondition parseRunFilter(const std::string& text, const RunTable& table) {
  DASH_THROW_UNLESS(text.size() <= 4000, "filter: longer than 4000 characters");
  return FilterParser(text, table).parse();
}

}  // namespace dash::http
