#pragma once
#include <string>

namespace dash {

/// The data folder (robot models, sample scenes): $DASHBENCH_DATA if set, else the source tree's data/.
std::string dataDirectory();

}  // namespace dash
