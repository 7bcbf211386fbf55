#pragma once
// Shared helpers of the scene tests: the format's example scene and the robot library (tests/common).
#include "tests/common/examples.h"
#include "tests/common/robot_library.h"
