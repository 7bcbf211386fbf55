// Unit tests of the server's parts: the runs filter, the static file resolver, the token file and
// the event hub.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "engine/log/results_db.h"
#include "server/http/event_hub.h"
#include "server/http/run_filter.h"
#include "server/http/run_table.h"
#include "server/http/static_files.h"
#include "server/http/token_file.h"
#include "tests/http/http_test_util.h"

namespace dash::http {
namespace {

using testing::TempDir;

class FilterTest : public ::testing::Test {
 protected:
  void SetUp() override { testing::fixtureDb(dir.file("f.db")); }
  RunTable table() const { return RunTable(log::ResultsDb(dir.file("f.db"), log::OpenMode::ReadOnly)); }
  TempDir dir;
};

TEST_F(FilterTest, ClausesBecomeBoundConditions) {
  const SqlCondition c = parseRunFilter("planner = lazy-dash and robots >= 8 AND status = \"solved\"", table());
  EXPECT_EQ(c.params.size(), 3u);
  EXPECT_EQ(std::get<std::string>(c.params[0]), "lazy-dash");
  EXPECT_DOUBLE_EQ(std::get<double>(c.params[1]), 8.0);
  EXPECT_EQ(std::get<std::string>(c.params[2]), "solved");
  EXPECT_NE(c.sql.find("json_extract(r.params, '$.\"robots\"') >= ?"), std::string::npos) << c.sql;
  EXPECT_EQ(c.sql.find("lazy-dash"), std::string::npos) << "values are bound, never spliced: " << c.sql;
}

TEST_F(FilterTest, OperatorsWithoutSpacesAndContains) {
  const SqlCondition c = parseRunFilter("objects<=4 and config ~ task and tag != baseline", table());
  EXPECT_EQ(c.params.size(), 3u);
  EXPECT_EQ(std::get<std::string>(c.params[1]), "%task%");
  EXPECT_NE(c.sql.find("NOT EXISTS"), std::string::npos);
  EXPECT_TRUE(parseRunFilter("   ", table()).sql.empty());
}

TEST_F(FilterTest, ErrorsNameTheProblem) {
  auto message = [&](const std::string& text) {
    try {
      parseRunFilter(text, table());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("robot = 4").find("unknown field 'robot'"), std::string::npos);
  EXPECT_NE(message("robots 4").find("expected an operator"), std::string::npos);
  EXPECT_NE(message("robots >= many").find("is a number"), std::string::npos);
  EXPECT_NE(message("planner = \"lazy").find("not closed"), std::string::npos);
  EXPECT_NE(message("robots = 2 robots = 4").find("expected 'and' or 'or'"), std::string::npos);
  EXPECT_NE(message("status =").find("expected a value"), std::string::npos);
  EXPECT_NE(message("(robots = 2 or robots = 4").find("expected ')'"), std::string::npos);
  EXPECT_NE(message("robots = 2)").find("')' without '('"), std::string::npos);
  EXPECT_NE(message("()").find("expected a field name"), std::string::npos);
  // Hostile nesting is refused before it costs anything.
  EXPECT_NE(message(std::string(5000, '(')).find("longer than 4000"), std::string::npos);
  EXPECT_NE(message(std::string(200, '(') + "robots = 2" + std::string(200, ')')).find("nested deeper"), std::string::npos);
}

TEST_F(FilterTest, OrBindsLooserThanAndAndParenthesesGroup) {
  const SqlCondition flat = parseRunFilter("planner = dash or robots = 2 and status = solved", table());
  ASSERT_EQ(flat.params.size(), 3u);
  EXPECT_EQ(flat.sql.rfind("(r.planner IS ?) OR ((", 0), 0u) << flat.sql;
  const SqlCondition grouped = parseRunFilter("(planner = dash or robots = 2) and status = solved", table());
  ASSERT_EQ(grouped.params.size(), 3u);
  EXPECT_EQ(grouped.sql.rfind("((r.planner IS ?) OR (", 0), 0u) << grouped.sql;
  EXPECT_NE(grouped.sql.find(") AND (r.status IS ?)"), std::string::npos) << grouped.sql;
  EXPECT_EQ(parseRunFilter("robots = 2 || robots = 4", table()).params.size(), 2u);
}

class StaticTest : public ::testing::Test {
 protected:
  void SetUp() override {
    namespace fs = std::filesystem;
    root = dir.path() / "web";
    fs::create_directories(root / "js");
    fs::create_directories(root / "node_modules/three/build");
    std::ofstream(root / "index.html") << "<!doctype html>";
    std::ofstream(root / "js/app.js") << "export {};";
    std::ofstream(root / ".secret.js") << "hidden";
    std::ofstream(root / "package.json") << "{}";
    std::ofstream(root / "node_modules/three/build/three.module.js") << "export {};";
    std::ofstream(root / "node_modules/three/package.json") << "{}";
    std::ofstream(dir.path() / "outside.js") << "secret";
    fs::create_symlink(dir.path() / "outside.js", root / "js/escape.js");
  }
  StaticLookup lookup(const std::string& url) const {
    StaticFile f;
    return StaticFiles(root.string()).lookup(url, f);
  }
  TempDir dir;
  std::filesystem::path root;
};

TEST_F(StaticTest, ServesFilesOfTheWebRootAndTheAllowList) {
  StaticFile f;
  const StaticFiles files(root.string());
  ASSERT_EQ(files.lookup("/", f), StaticLookup::kFound);
  EXPECT_EQ(f.mime_type, "text/html; charset=utf-8");
  ASSERT_EQ(files.lookup("/js/app.js", f), StaticLookup::kFound);
  EXPECT_EQ(f.mime_type, "text/javascript; charset=utf-8");
  ASSERT_EQ(files.lookup("/vendor/three/three.module.js", f), StaticLookup::kFound);
  EXPECT_NE(f.path.find("node_modules/three/build/three.module.js"), std::string::npos);
}

TEST_F(StaticTest, RefusesEverythingElse) {
  for (const char* url : {"/../outside.js", "/js/../../outside.js", "/js/./app.js", "//etc/passwd", "/js\\..\\x.js",
                          "/node_modules/three/build/three.module.js", "/.secret.js", "/js/"}) {
    EXPECT_EQ(lookup(url), StaticLookup::kForbidden) << url;
  }
  EXPECT_EQ(lookup("/js/escape.js"), StaticLookup::kForbidden) << "a symbolic link out of the web root";
  EXPECT_EQ(lookup("/package.json"), StaticLookup::kNotFound) << "only known file types are served";
  EXPECT_EQ(lookup("/vendor/three/package.json"), StaticLookup::kNotFound);
  EXPECT_EQ(lookup("/missing.js"), StaticLookup::kNotFound);
  EXPECT_EQ(lookup("relative.js"), StaticLookup::kForbidden);
}

TEST(TokenFile, CreatedOnceWithOwnerOnlyPermissions) {
  TempDir dir;
  const std::string path = dir.file("sub/token");
  const TokenFile first = loadOrCreateToken(path);
  EXPECT_TRUE(first.created);
  EXPECT_EQ(first.token.size(), 64u);
  EXPECT_EQ(first.token.find_first_not_of("0123456789abcdef"), std::string::npos);
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const TokenFile second = loadOrCreateToken(path);
  EXPECT_FALSE(second.created);
  EXPECT_EQ(second.token, first.token);
  EXPECT_FALSE(second.too_permissive);
  EXPECT_NE(newRandomToken(), newRandomToken());
}

TEST(TokenFile, EmptyOrOpenFiles) {
  TempDir dir;
  std::ofstream(dir.file("empty")) << "\n";
  EXPECT_THROW(loadOrCreateToken(dir.file("empty")), InputError);
  std::ofstream(dir.file("open")) << "abc\n";
  chmod(dir.file("open").c_str(), 0644);
  const TokenFile t = loadOrCreateToken(dir.file("open"));
  EXPECT_EQ(t.token, "abc");
  EXPECT_TRUE(t.too_permissive);
}

TEST(EventHub, DeliversInOrderAndReportsGaps) {
  EventHub hub(3);
  const std::uint64_t start = hub.lastSeq();
  hub.publish("a", "k1", "{}");
  hub.publish("b", "k2", "{\"x\":1}");
  HubWait w = hub.waitAfter(start, std::chrono::milliseconds(0));
  ASSERT_EQ(w.messages.size(), 2u);
  EXPECT_EQ(w.messages[0].event, "a");
  EXPECT_EQ(EventHub::formatSse(w.messages[1]), "id: 2\nevent: b\ndata: {\"x\":1}\n\n");
  EXPECT_FALSE(w.gap);
  for (int i = 0; i < 5; ++i) hub.publish("c", "", "{}");
  w = hub.waitAfter(2, std::chrono::milliseconds(0));
  EXPECT_TRUE(w.gap) << "messages 3 and 4 fell out of the ring of 3";
  EXPECT_EQ(w.messages.size(), 3u);
  w = hub.waitAfter(hub.lastSeq(), std::chrono::milliseconds(20));
  EXPECT_TRUE(w.messages.empty());
  hub.close();
  EXPECT_TRUE(hub.waitAfter(hub.lastSeq(), std::chrono::seconds(10)).closed);
}

}  // namespace
}  // namespace dash::http
