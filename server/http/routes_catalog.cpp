// GET /api/health, /api/token, /api/info, /api/scenarios, /api/scenarios/FAMILY, /api/planners, /api/robots.

#include <filesystem>
#include <fstream>

#include "engine/core/paths.h"
#include "engine/core/planner_params.h"
#include "engine/log/db_tools.h"
#include "engine/log/results_db.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/routes.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

Json familyJson(const ScenarioFamily& f) {
  Json params = Json::array();
  for (const ParamSpec& p : f.params) {
    params.push_back({{"name", p.name},
                      {"default", p.default_value},
                      {"min", p.min},
                      {"max", p.max},
                      {"even_only", p.even_only},
                      {"range", p.rangeText()},
                      {"meaning", p.meaning}});
  }
  return {{"name", f.name}, {"summary", f.summary}, {"params", params}};
}

Json plannersJson() {
  // The settings a batch spec accepts per planner (batch_spec.h); test_fault is for tests only.
  Json settings = Json::array({{{"name", "task_only"},
                                {"type", "bool"},
                                {"default", false},
                                {"meaning", "stop after the task layer (an unvalidated schedule, no motions)"}}});
  Json list = Json::array();
  for (const std::string& name : plannerNames()) {
    // The named parameters (`dashbench plan --params`); a batch spec takes them in "settings" too.
    Json parameters = Json::array();
    for (const ParamInfo& p : plannerParameters(name)) {
      const char* type = p.type == ParamType::kBool ? "bool" : p.type == ParamType::kInt ? "int" : "real";
      Json item{{"name", p.name}, {"type", type}, {"default", p.default_value}, {"paper", p.paper_value},
                {"description", p.description}};
      if (p.type != ParamType::kBool) item.update({{"min", p.min}, {"max", p.max}});
      parameters.push_back(std::move(item));
    }
    list.push_back({{"name", name}, {"settings", settings}, {"parameters", parameters}});
  }
  return list;
}

/// The robot model files (data/robots/*.json) as they are: the 3D view poses their collision bodies.
Json robotModelsJson() {
  Json models = Json::object();
  const std::filesystem::path dir = std::filesystem::path(dataDirectory()) / "robots";
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    const Json model = Json::parse(in, nullptr, false);
    if (model.is_object() && model.contains("model") && model["model"].is_string()) {
      models[model["model"].get<std::string>()] = model;
    }
  }
  return models;
}

}  // namespace

void registerCatalogRoutes(httplib::Server& server, ApiContext& ctx) {
  // Whether a token is this server's (the dashboard's Token box checks what was pasted): 200 or 401.
  server.Get("/api/token", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               requireToken(req, ctx.token);
               replyJson(res, 200, jsonText(Json{{"valid", true}}));
             }));

  server.Get("/api/health", guarded([&ctx](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200,
                         jsonText(Json{{"ok", true},
                                       {"version", DASHBENCH_VERSION},
                                       {"db", ctx.db_path},
                                       {"dispatch", ctx.dispatch_mounted},
                                       {"max_body_bytes", ctx.max_body_bytes},
                                       {"max_workers", ctx.batches->options().max_workers}}));
             }));

  server.Get("/api/info", guarded([&ctx](const httplib::Request&, httplib::Response& res) {
               const log::ResultsDb db(ctx.db_path, log::OpenMode::ReadOnly);
               const log::DbInfo info = db.info();
               replyJson(res, 200,
                         jsonText(Json{{"path", info.path},
                                       {"schema_version", info.schema_version},
                                       {"runs", info.runs},
                                       {"runs_by_status", info.runs_by_status},
                                       {"experiments", info.experiments},
                                       {"planner_configs", info.planner_configs},
                                       {"batches", info.batches},
                                       {"events", info.events}}));
             }));

  server.Get("/api/scenarios", guarded([](const httplib::Request&, httplib::Response& res) {
               Json list = Json::array();
               for (const ScenarioFamily& f : scenarioFamilies()) list.push_back(familyJson(f));
               replyJson(res, 200, jsonText(Json{{"families", list}, {"planners", plannersJson()}}));
             }));

  server.Get(R"(/api/scenarios/([A-Za-z0-9_\-]+))", guarded([](const httplib::Request& req, httplib::Response& res) {
               const ScenarioFamily* f = findScenarioFamily(req.matches[1]);
               if (f == nullptr) throw HttpError(404, "no scenario family '" + std::string(req.matches[1]) + "'");
               replyJson(res, 200, jsonText(familyJson(*f)));
             }));

  server.Get("/api/robots", guarded([](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200, jsonText(Json{{"models", robotModelsJson()}}));
             }));

  server.Get("/api/planners", guarded([](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200, jsonText(Json{{"planners", plannersJson()}}));
             }));
}

}  // namespace dash::http
