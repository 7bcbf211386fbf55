#pragma once
// How a configuration's runs are named as a series in comparisons (issue 37 item 3: the Compare page
// and `report --figures` show the profile as part of the series).
#include <string>

namespace dash::log {

/// The series a run of configuration `config` is drawn as: the configuration, followed by the
/// profile the run ran under (`--profile`, "profile" in its settings JSON) unless the configuration's
/// name has it as a word already: "lazy-dash (default)", "dash-paper". So two profiles of one planner
/// are two series and each says which it is (`report --figures`, /api/series; the Compare page's
/// seriesName in web/js/compare_data.js follows the same rule).
std::string seriesName(const std::string& config, const std::string& settings_json);

}  // namespace dash::log
