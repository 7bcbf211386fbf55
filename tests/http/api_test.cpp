// The JSON API against the server on loopback, on a fixture database: catalog, runs (filter, sort,
// page, CSV), one run (detail, events, timeline, plan, scene), tags and notes, series, SQL console.
#include "engine/log/results_db.h"
#include "tests/http/http_test_util.h"

namespace dash::http::testing {
namespace {

using ApiTest = ServerTest;

TEST_F(ApiTest, HealthAndInfo) {
  const Reply h = http->get("/api/health");
  ASSERT_EQ(h.status, 200) << h.body;
  EXPECT_TRUE(h.json()["ok"].get<bool>());
  EXPECT_EQ(h.json()["db"], db_path);
  EXPECT_EQ(h.header("Content-Type"), "application/json");
  const Reply i = http->get("/api/info");
  ASSERT_EQ(i.status, 200);
  EXPECT_EQ(i.json()["runs"], 3);
  EXPECT_EQ(i.json()["runs_by_status"]["solved"], 2);
}

TEST_F(ApiTest, DispatchApiIsMountedWithTheServersToken) {
  if (!server->dispatchMounted()) GTEST_SKIP() << "this build has no server/dispatch";
  const Reply list = http->get("/api/controllers", kToken);
  ASSERT_EQ(list.status, 200) << list.body;
  EXPECT_EQ(list.json()["controllers"], Json::array());
  EXPECT_EQ(http->get("/api/controllers").status, 401);
  EXPECT_EQ(http->get("/api/dispatch", kToken).status, 404) << "no dispatch yet";
  EXPECT_TRUE(http->get("/api/health").json()["dispatch"].get<bool>());
}

TEST_F(ApiTest, ScenarioFamiliesPlannersAndRobots) {
  const Json s = http->get("/api/scenarios").json();
  bool sorting = false;
  for (const Json& f : s["families"]) {
    if (f["name"] != "sorting") continue;
    sorting = true;
    EXPECT_EQ(f["params"][0]["name"], "robots");
    EXPECT_LE(f["params"][0]["min"].get<int>(), f["params"][0]["default"].get<int>());
  }
  EXPECT_TRUE(sorting);
  EXPECT_EQ(s["planners"][0]["name"], "lazy-dash");
  EXPECT_EQ(http->get("/api/scenarios/sorting").json()["name"], "sorting");
  const Reply missing = http->get("/api/scenarios/nope");
  EXPECT_EQ(missing.status, 404);
  EXPECT_NE(missing.json()["error"].get<std::string>().find("nope"), std::string::npos);
  const Json robots = http->get("/api/robots").json();
  EXPECT_EQ(robots["models"]["ur5e"]["kinematics"]["d"][0], 0.1625);
  EXPECT_TRUE(robots["models"].contains("gantry3"));
  EXPECT_EQ(http->get("/api/planners").json()["planners"][0]["settings"][0]["name"], "task_only");
}

TEST_F(ApiTest, RunsFilterSortPage) {
  Json all = http->get("/api/runs").json();
  EXPECT_EQ(all["total"], 3);
  ASSERT_EQ(all["runs"].size(), 3u);
  EXPECT_EQ(all["runs"][0]["robots"], 2) << "scenario parameters are columns";
  const Json solved = http->get("/api/runs?q=status%20%3D%20solved%20and%20objects%20%3D%202").json();
  EXPECT_EQ(solved["total"], 2);
  for (const Json& r : solved["runs"]) EXPECT_EQ(r["status"], "solved");
  const Json config = http->get("/api/runs?q=config%20%3D%20lazy-task").json();
  ASSERT_EQ(config["total"], 1);
  EXPECT_EQ(config["runs"][0]["uuid"], fixture.task_only);
  const Json by_time = http->get("/api/runs?sort=total_time&order=asc").json();
  EXPECT_EQ(by_time["runs"][0]["uuid"], fixture.task_only);
  EXPECT_EQ(by_time["runs"][2]["uuid"], fixture.timeout);
  const Json page = http->get("/api/runs?sort=total_time&order=asc&limit=1&offset=1").json();
  ASSERT_EQ(page["runs"].size(), 1u);
  EXPECT_EQ(page["runs"][0]["uuid"], fixture.solved);
  EXPECT_EQ(page["total"], 3);
  const Json two = http->get("/api/runs?uuids=" + fixture.solved + "," + fixture.timeout).json();
  EXPECT_EQ(two["total"], 2);

  const Reply bad = http->get("/api/runs?q=robot%20%3D%202");
  EXPECT_EQ(bad.status, 400);
  EXPECT_NE(bad.json()["error"].get<std::string>().find("unknown field 'robot'"), std::string::npos);
  EXPECT_EQ(http->get("/api/runs?sort=nope").status, 400);
  EXPECT_EQ(http->get("/api/runs?limit=0").status, 400);
  EXPECT_EQ(http->get("/api/runs?order=up").status, 400);
  const Json cols = http->get("/api/runs/columns").json();
  EXPECT_EQ(cols["parameters"], Json::array({"objects", "robots"}));
}

TEST_F(ApiTest, CsvExportOfAFilteredList) {
  const Reply csv = http->get("/api/runs.csv?q=status%20%3D%20solved&columns=uuid,status,objects&sort=id&order=asc");
  ASSERT_EQ(csv.status, 200) << csv.body;
  EXPECT_EQ(csv.header("Content-Type"), "text/csv; charset=utf-8");
  EXPECT_NE(csv.header("Content-Disposition").find("runs.csv"), std::string::npos);
  EXPECT_EQ(csv.body, "uuid,status,objects\n" + fixture.solved + ",solved,2\n" + fixture.task_only + ",solved,2\n");
  EXPECT_EQ(http->get("/api/runs.csv?columns=nope").status, 400);
}

TEST_F(ApiTest, OneRunWithPhasesEventsTimelinePlanAndScene) {
  const Reply d = http->get("/api/runs/" + fixture.solved);
  ASSERT_EQ(d.status, 200) << d.body;
  const Json run = d.json();
  EXPECT_EQ(run["run"]["status"], "solved");
  EXPECT_EQ(run["params"]["objects"], 2);
  EXPECT_EQ(run["event_counts"]["constraint"], 3);
  EXPECT_EQ(run["event_counts"]["task_space_expansion"], 1);
  EXPECT_GT(run["phases"]["task_query"].get<double>(), -1.0);
  EXPECT_EQ(run["counters"]["roadmap_vertices"], 30);
  EXPECT_FALSE(run["phase_iterations"].empty());
  EXPECT_EQ(http->get("/api/runs/00000000-0000-4000-8000-000000000000").status, 404);

  const Json events = http->get("/api/runs/" + fixture.solved + "/events?limit=5&offset=2").json();
  EXPECT_EQ(events["events"].size(), 5u);
  EXPECT_GT(events["total"].get<int>(), 20);
  const Json constraints = http->get("/api/runs/" + fixture.solved + "/events?type=constraint").json();
  EXPECT_EQ(constraints["total"], 3);
  for (const Json& e : constraints["events"]) EXPECT_EQ(e["type"], "constraint");
  EXPECT_EQ(http->get("/api/runs/" + fixture.solved + "/events?type=nope").status, 400);

  const Json tl = http->get("/api/runs/" + fixture.solved + "/timeline").json();
  ASSERT_EQ(tl["constraints"].size(), 3u);
  EXPECT_EQ(tl["constraints"][0]["conflict"], "place of O1 collides with O0");
  EXPECT_EQ(tl["expansions"][0]["object_label"], "O1");
  EXPECT_FALSE(tl["progress"]["rows"].empty());
  EXPECT_FALSE(tl["additions"].empty());

  const Reply plan = http->get("/api/runs/" + fixture.solved + "/plan");
  ASSERT_EQ(plan.status, 200);
  EXPECT_EQ(plan.json()["format"], "dashbench.plan/1");
  EXPECT_EQ(http->get("/api/runs/" + fixture.timeout + "/plan").status, 404);

  const Reply scene = http->get("/api/runs/" + fixture.solved + "/scene");
  ASSERT_EQ(scene.status, 200) << scene.body;
  EXPECT_EQ(scene.json()["format"], "dashbench.scene/1");
  EXPECT_EQ(scene.json()["robots"].size(), 2u);
  EXPECT_EQ(scene.json()["objects"].size(), 2u);
  EXPECT_EQ(scene.json()["generator"]["seed"], 1);
}

TEST_F(ApiTest, TagsAndNotesNeedTheToken) {
  const std::string base = "/api/runs/" + fixture.solved;
  EXPECT_EQ(http->post(base + "/tags", R"({"add":["baseline"]})", "").status, 401);
  EXPECT_EQ(http->post(base + "/tags", R"({"add":["baseline"]})", "wrong").status, 401);
  const Reply added = http->post(base + "/tags", R"({"add":["baseline","paper fig 3"]})");
  ASSERT_EQ(added.status, 200) << added.body;
  EXPECT_EQ(added.json()["tags"], Json::array({"baseline", "paper fig 3"}));
  EXPECT_EQ(http->get("/api/runs?q=tag%20%3D%20baseline").json()["total"], 1);
  EXPECT_EQ(http->get("/api/runs?q=tag%20%3D%20baseline").json()["runs"][0]["tags"], "baseline,paper fig 3");
  const Reply removed = http->del(base + "/tags/baseline");
  ASSERT_EQ(removed.status, 200);
  EXPECT_EQ(removed.json()["tags"], Json::array({"paper fig 3"}));
  EXPECT_EQ(http->post(base + "/tags", R"({"add":["a,b"]})").status, 400);
  EXPECT_EQ(http->post(base + "/tags", R"({"color":"red"})").status, 400);
  EXPECT_EQ(http->post("/api/runs/00000000-0000-4000-8000-000000000000/tags", R"({"add":["x"]})").status, 404);

  EXPECT_EQ(http->put(base + "/note", R"({"note":"first try"})", "").status, 401);
  const Reply note = http->put(base + "/note", R"({"note":"first try"})");
  ASSERT_EQ(note.status, 200);
  EXPECT_EQ(note.json()["note"], "first try");
  EXPECT_EQ(http->get(base).json()["note"], "first try");
  EXPECT_EQ(http->put(base + "/note", Json{{"note", std::string(20000, 'x')}}.dump()).status, 400);
  EXPECT_EQ(http->put(base + "/note", R"({"note": 3})").status, 400);
}

// Grouped by configuration, a configuration's runs under two profiles are two series, each named
// with its profile (log::seriesName), as on the Compare page and in `report --figures`.
TEST_F(ApiTest, SeriesByConfigurationNameTheProfileTheirRunsRanUnder) {
  {
    dash::log::ResultsDb db(db_path);
    for (const std::string profile : {"default", "paper"}) {
      const std::string uuid = db.beginRun(dash::log::RunMetadata{.family = "wall", .params_json = R"({"objects":2})",
                                                            .seed = 1, .planner = "dash",
                                                            .planner_settings_json = R"({"profile":")" + profile + "\"}",
                                                            .planner_config_name = "dash"});
      dash::log::RunSummary s;
      s.status = dash::log::RunStatus::Solved;
      s.total_time = 1.0;
      db.finishRun(uuid, s);
    }
  }
  const Reply r = http->get("/api/series?family=wall&x=objects");
  ASSERT_EQ(r.status, 200) << r.body;
  std::vector<std::string> names;
  const Json body = r.json();
  for (const Json& g : body["groups"]) names.push_back(g["group"].get<std::string>());
  EXPECT_EQ(names, (std::vector<std::string>{"dash (default)", "dash (paper)"}));
}

TEST_F(ApiTest, SeriesForTheComparePlots) {
  const Reply r = http->get("/api/series?family=sorting&x=objects");
  ASSERT_EQ(r.status, 200) << r.body;
  const Json s = r.json();
  ASSERT_EQ(s["groups"].size(), 3u);  // lazy-dash x 2, lazy-dash x 4, lazy-task x 2
  const Json& g = s["groups"][0];
  EXPECT_EQ(g["group"], "lazy-dash");
  EXPECT_EQ(g["x"], 2);
  EXPECT_EQ(g["success_rate"], 1.0);
  EXPECT_EQ(g["metrics"]["task_vertices"]["median"], 6);
  EXPECT_EQ(g["metrics"]["total_time"]["values"], Json::array({1.5}));
  const Json& timeout = s["groups"][1];
  EXPECT_EQ(timeout["success_rate"], 0.0);
  EXPECT_EQ(timeout["metrics"]["total_time"]["n"], 0) << "medians over solved runs only by default";
  const Json all = http->get("/api/series?family=sorting&x=objects&include_unsolved=1").json();
  EXPECT_EQ(all["groups"][1]["metrics"]["total_time"]["n"], 1);
  EXPECT_EQ(http->get("/api/series?family=sorting&x=objects&group_by=planner").json()["groups"].size(), 2u);
  const Json split = http->get("/api/series?family=sorting&x=robots&split=objects").json();
  ASSERT_EQ(split["groups"].size(), 3u);
  EXPECT_EQ(split["groups"][0]["group"], "lazy-dash · objects=2");
  EXPECT_EQ(split["groups"][1]["group"], "lazy-dash · objects=4");
  EXPECT_EQ(http->get("/api/series?family=sorting&x=objects&split=objects").status, 400);
  EXPECT_EQ(http->get("/api/series?family=sorting&x=walls").status, 400);
  EXPECT_EQ(http->get("/api/series?x=objects").status, 400);
  const Json o = http->get("/api/compare/overview").json();
  EXPECT_EQ(o["families"][0]["family"], "sorting");
  EXPECT_EQ(o["families"][0]["configs"], Json::array({"lazy-dash", "lazy-task"}));
}

TEST_F(ApiTest, ReadOnlySqlConsole) {
  const Reply ok = http->post(
      "/api/query", R"({"sql":"SELECT status, count(*) AS n FROM dash_runs GROUP BY status ORDER BY status"})", "");
  ASSERT_EQ(ok.status, 200) << ok.body;
  EXPECT_EQ(ok.json()["columns"], Json::array({"status", "n"}));
  EXPECT_EQ(ok.json()["rows"], Json::parse(R"([["solved",2],["timeout",1]])"));
  const Reply limited = http->post("/api/query", R"({"sql":"SELECT * FROM dash_events","max_rows":2})", "");
  EXPECT_EQ(limited.json()["rows"].size(), 2u);
  EXPECT_TRUE(limited.json()["truncated"].get<bool>());
  for (const char* sql : {"DELETE FROM dash_runs", "UPDATE dash_runs SET status = 'solved'", "DROP TABLE dash_runs",
                          "ATTACH DATABASE '/tmp/x.db' AS x", "PRAGMA journal_mode = DELETE",
                          "SELECT 1; DELETE FROM dash_runs", "BEGIN"}) {
    const Reply refused = http->post("/api/query", Json{{"sql", sql}}.dump(), "");
    EXPECT_EQ(refused.status, 403) << sql << ": " << refused.body;
    EXPECT_NE(refused.json()["error"].get<std::string>().find("refused"), std::string::npos) << sql;
    EXPECT_EQ(refused.json()["error"].get<std::string>().find("refused: refused"), std::string::npos) << sql;
  }
  EXPECT_EQ(http->get("/api/info").json()["runs"], 3) << "nothing was deleted";
  EXPECT_EQ(http->post("/api/query", R"({"sql":"SELECT * FROM no_such_table"})", "").status, 400);
  EXPECT_EQ(http->post("/api/query", R"({"query":"SELECT 1"})", "").status, 400);
  EXPECT_EQ(http->post("/api/query", R"({"sql":"SELECT 1","max_rows":0})", "").status, 400);
  EXPECT_GE(http->get("/api/query/examples").json()["examples"].size(), 5u);
}

}  // namespace
}  // namespace dash::http::testing
