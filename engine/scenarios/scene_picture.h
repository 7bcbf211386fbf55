#pragma once
// A top-down picture of a scene (x to the right, y up), for the README and `dashbench scenario --png`:
// obstacles shaded by height (taller is darker), resting surfaces outlined, robots as their base
// discs with a tick towards their home pose (a gantry as its reach rectangle and bridge), and objects
// drawn over everything (an x-ray view into shelves): filled squares at their start, outlined squares
// at their goal, coloured by the robot nearest their goal; objects whose goal is their start in amber,
// fixed objects in grey.
#include "engine/scenarios/png_writer.h"
#include "engine/scene/scene.h"

namespace dash {

struct PictureOptions {
  int max_side_pixels = 900;  ///< the longer side of the picture
  double margin = 0.05;       ///< metres around the scene's extent
};

RgbImage renderScene(const Scene& scene, const PictureOptions& options = {});

}  // namespace dash
