#pragma once
// JSON codec for dashbench.scene/1. Parsing validates strictly and throws InputError with the path of
// the offending field, e.g. "robots[2].base.q: quaternion is not unit length". Writing is
// deterministic: the same scene always gives byte-identical text.
#include <memory>
#include <string>

#include "engine/core/check.h"  // InputError
#include "engine/scene/scene.h"

namespace dash {

/// Parses and validates a scene; robot models are resolved in `library` (kept by the scene).
/// `source_name` prefixes error messages (a file name, or empty).
Scene parseScene(const std::string& json_text, std::shared_ptr<const RobotLibrary> library,
                 const std::string& source_name = "");
/// Reads and parses a scene file; throws InputError if it cannot be read or is invalid.
Scene loadScene(const std::string& path, std::shared_ptr<const RobotLibrary> library);

/// Pretty-printed JSON (indent 1, fields in contract order).
std::string sceneToJson(const Scene& scene);
/// Writes sceneToJson(scene) to `path`; throws InputError if the file cannot be written.
void saveScene(const Scene& scene, const std::string& path);

}  // namespace dash
