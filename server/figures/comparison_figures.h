#pragma once
// The paper's comparison figures (Lazy-DaSH paper, Figs. "representation_size" and "planning_time",
// and the success rates behind its claims), generated from a results database. Per scenario family:
//   <family>-sizes    H_T and H_M vertices and hyperarcs (log scale), medians over solved runs;
//   <family>-time     construction (task + motion), query (task query + task conflict detection +
//                     motion query), conflict resolution, and total seconds, medians over solved runs,
//                     the same y range in every panel (as the paper's);
//   <family>-success  solved / finished runs, in percent; sizes the axis stop rule skipped are crosses.
// Each as SVG (written here) and PNG (rsvg-convert, Debian package librsvg2-bin).
#include <string>
#include <vector>

#include "engine/log/results_db.h"
#include "server/figures/figure_data.h"
#include "server/figures/svg_chart.h"

namespace dash::figures {

struct FigureOptions {
  std::string batch_id;  ///< empty: every run of the database
  std::string dir;       ///< created if missing
  bool png = true;
  std::string rsvg_convert = "rsvg-convert";
};

struct FigureFiles {
  std::vector<std::string> families;
  std::vector<std::string> files;  ///< every file written
};

/// Throws InputError when the directory cannot be written, there is nothing to plot, or (with png)
/// rsvg-convert fails.
FigureFiles writeComparisonFigures(const log::ResultsDb& db, const FigureOptions& options);

Figure sizeFigure(const FamilyData& family);
Figure timeFigure(const FamilyData& family);
Figure successFigure(const FamilyData& family);

/// SVG file -> PNG file with rsvg-convert (no shell); throws InputError when it fails.
void convertToPng(const std::string& rsvg_convert, const std::string& svg, const std::string& png);

}  // namespace dash::figures
