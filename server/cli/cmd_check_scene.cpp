#include <cstdio>

#include "engine/collision/scene_check.h"
#include "engine/core/check.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene_json.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kCheckSceneHelp;
const char* const kCheckSceneHelp =
    "usage: dashbench check-scene FILE\n"
    "Load a dashbench.scene/1 file and report every problem found: robots colliding at home, objects\n"
    "colliding at their start or goal, objects not resting on a surface or another object, objects no\n"
    "robot can grasp at their start or goal. A grasp counts if some robot with the \"grasp\" capability\n"
    "can hold the object there without a collision among the obstacles and the fixed objects: other\n"
    "movable objects are not in the way for it, since a plan may move them first or place them later\n"
    "(a rear shelf slot blocked by the object that goes in front of it is fine; one blocked by an\n"
    "obstacle or a fixed object is not). Exit 0 if none, 1 if problems, 2 if the file is invalid.\n";

int runCheckScene(const std::vector<std::string>& words) {
  Args args(words, {});
  DASH_THROW_UNLESS(args.positional().size() == 1, "expected exactly one scene file (see --help)");
  const std::string& path = args.positional()[0];
  const Scene scene = loadScene(path, RobotLibrary::loadDefault());
  const std::vector<std::string> problems = findSceneProblems(scene);
  for (const std::string& problem : problems) std::printf("%s: %s\n", path.c_str(), problem.c_str());
  if (!problems.empty()) {
    std::printf("%s: %zu problem%s\n", path.c_str(), problems.size(), problems.size() == 1 ? "" : "s");
    return kExitProblems;
  }
  std::printf("%s: ok (%zu robots, %zu obstacles, %zu objects)\n", path.c_str(), scene.robots.size(),
              scene.obstacles.size(), scene.objects.size());
  return kExitOk;
}

}  // namespace dash::cli
