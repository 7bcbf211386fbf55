// `dashbench fk` and `dashbench ik`: JSON output and exit codes (0 ok, 2 bad input).
#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/robots/kinematics.h"
#include "tests/common/cli_run.h"

namespace dash {
namespace {

using nlohmann::json;

using RunResult = test::CliRun;

RunResult runCli(const std::string& arguments) { return test::runDashbench(arguments, test::Stderr::kDrop); }

Pose poseFromJson(const json& j) {
  return makePose(Vec3(j["p"][0], j["p"][1], j["p"][2]), quatFromXYZW({j["q"][0], j["q"][1], j["q"][2], j["q"][3]}));
}

const RobotModel& ur5e() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib->get("ur5e");
}

TEST(CliFk, Ur5eZeroConfiguration) {
  const RunResult r = runCli("fk --robot ur5e --q 0,0,0,0,0,0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  const Pose flange = poseFromJson(j.at("flange"));
  const Pose tcp = poseFromJson(j.at("tcp"));
  EXPECT_LT((flange.translation() - Vec3(-0.8172, -0.2329, 0.0628)).norm(), 1e-12);
  EXPECT_LT((tcp.translation() - Vec3(-0.8172, -0.3899, 0.0628)).norm(), 1e-12);
  ASSERT_EQ(j["tcp"]["q"].size(), 4u);
  EXPECT_GE(j["tcp"]["q"][3].get<double>(), 0.0);
}

TEST(CliFk, BasePoseAndGantry) {
  RunResult r =
      runCli("fk --robot ur5e --q 0.1,-1,1.2,-0.3,0.5,2 --base 1,2,0.5,0,0,0.7071067811865476,0.7071067811865476");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Pose X_WB = makePose(Vec3(1, 2, 0.5), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  JointVector q(6);
  q << 0.1, -1, 1.2, -0.3, 0.5, 2;
  const FkResult fk = forwardKinematics(ur5e(), X_WB, q);
  const json j = json::parse(r.output);
  EXPECT_TRUE(poseFromJson(j["tcp"]).isApprox(fk.X_WT, 1e-12));
  EXPECT_TRUE(poseFromJson(j["flange"]).isApprox(fk.X_WF, 1e-12));

  r = runCli("fk --robot gantry3 --q 0.1,0.2,0.05");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json g = json::parse(r.output);
  EXPECT_NEAR(g["tcp"]["p"][2].get<double>(), 0.35, 1e-15);
  EXPECT_NEAR(std::abs(g["tcp"]["q"][0].get<double>()), 1.0, 1e-15);  // half turn about x
}

TEST(CliIk, Ur5eSolutionsReproduceTheTarget) {
  JointVector home(6);
  home << 0, -M_PI / 2, M_PI / 2, -M_PI / 2, -M_PI / 2, 0;
  const Pose X_WT = forwardKinematics(ur5e(), Pose::Identity(), home).X_WT;
  const auto quat = quatXYZW(X_WT);
  char tcp[256];
  std::snprintf(tcp, sizeof tcp, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", X_WT.translation().x(),
                X_WT.translation().y(), X_WT.translation().z(), quat[0], quat[1], quat[2], quat[3]);
  const RunResult r = runCli(std::string("ik --robot ur5e --tcp ") + tcp);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  ASSERT_TRUE(j.is_array());
  EXPECT_EQ(j.size(), 8u);
  bool found_home = false;
  for (const auto& s : j) {
    ASSERT_EQ(s.size(), 6u);
    JointVector q(6);
    for (int i = 0; i < 6; ++i) q[i] = s[static_cast<std::size_t>(i)].get<double>();
    EXPECT_TRUE(forwardKinematics(ur5e(), Pose::Identity(), q).X_WT.isApprox(X_WT, 1e-9));
    if ((q - home).cwiseAbs().maxCoeff() < 1e-9) found_home = true;
  }
  EXPECT_TRUE(found_home);
}

TEST(CliIk, UnreachableAndGantry) {
  RunResult r = runCli("ik --robot ur5e --tcp 3,0,0,0,0,0,1");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_EQ(json::parse(r.output), json::array());
  r = runCli("ik --robot gantry3 --tcp 0.1,0.2,0.35,1,0,0,0");
  ASSERT_EQ(r.exit_code, 0);
  const json j = json::parse(r.output);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_NEAR(j[0][2].get<double>(), 0.05, 1e-12);
  r = runCli("ik --robot gantry3 --tcp 0.1,0.2,0.35,0,0,0,1");  // tool up: no solution
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_TRUE(json::parse(r.output).empty());
}

TEST(CliFkIk, BadInputExitsWithTwo) {
  for (const char* args : {"fk --robot ur6 --q 0,0,0,0,0,0", "fk --robot ur5e --q 0,0,0",
                           "fk --robot ur5e --q 0,0,0,0,0,nan", "fk --robot ur5e --q 0,0,0,0,0,x",
                           "fk --robot ur5e", "fk --q 0,0,0,0,0,0",
                           "fk --robot ur5e --q 0,0,0,0,0,0 --base 0,0,0,0,0,0,2",
                           "fk --robot ur5e --q 0,0,0,0,0,0 --bogus 1",
                           "ik --robot ur5e --tcp 0.3,0.1,0.2,0,0,0,1.1", "ik --robot ur5e --tcp 0.3,0.1,0.2,0,0,1",
                           "ik --robot ur5e --tcp 0.3,0.1,inf,0,0,0,1", "ik --robot nope --tcp 0.3,0.1,0.2,0,0,0,1",
                           "ik --robot ur5e"}) {
    const RunResult r = runCli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_TRUE(r.output.empty()) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace dash
