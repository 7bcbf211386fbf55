#pragma once
// A small SVG chart writer for the comparison figures: one figure is a row of panels sharing one
// legend; a panel has labelled axes (linear or log10 y), a title, and line series with point
// markers. Points a planner did not run (the batch's axis stop rule) are drawn as crosses on the x
// axis. The markup names what it draws (class="panel" data-title, class="series" data-name) so that
// tests and scripts can find the panels and series.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dash::figures {

struct Series {
  std::string name;
  std::string color = "#1f77b4";
  bool dashed = false;
  std::vector<std::pair<double, double>> points;  ///< (x, y), drawn in x order
  std::vector<double> skipped_x;                  ///< sizes not run (crosses on the x axis)
};

struct Panel {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_y = false;
  std::optional<std::pair<double, double>> y_range;  ///< unset: from the data
  /// Grouped bars instead of lines: one slot per distinct x, one bar per series in it (rates that
  /// often coincide, such as 100 % solved, stay visible side by side). Dashed series are drawn pale.
  bool bars = false;
  std::vector<Series> series;
};

struct Figure {
  std::string title;
  std::vector<Panel> panels;
};

/// The figure as a standalone SVG document.
std::string renderSvg(const Figure& figure);

/// The y range covering every point of `panels` (log: positive values only, padded to decades).
std::pair<double, double> sharedRange(const std::vector<Panel>& panels, bool log_y);

/// A tick label as people write numbers, never in exponent form: "0.001", "0.25", "40", "10,000".
std::string tickLabel(double v);

/// Escapes &, <, >, " for SVG text and attributes.
std::string escapeXml(const std::string& text);

}  // namespace dash::figures
