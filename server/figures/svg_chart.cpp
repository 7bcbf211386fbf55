#include "server/figures/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>

namespace dash::figures {

std::string tickLabel(double v) {
  if (v == 0) return "0";
  const double a = std::fabs(v);
  char buf[64];
  if (a >= 1e4) {
    std::snprintf(buf, sizeof buf, "%.0f", a);
    std::string digits = buf, out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
      if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
      out += digits[i];
    }
    return (v < 0 ? "-" : "") + out;
  }
  if (a >= 1e-2) {
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }
  // Three significant digits at most, in fixed notation, trailing zeros dropped.
  const int decimals = std::min(15, static_cast<int>(std::ceil(-std::log10(a))) + 2);
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string out = buf;
  while (out.back() == '0') out.pop_back();
  if (out.back() == '.') out.pop_back();
  return out;
}

namespace {

constexpr double kPanelWidth = 330, kPanelHeight = 270;
constexpr double kLeft = 62, kRight = 12, kTop = 30, kBottom = 46;  // plot margins inside a panel
constexpr double kTitleHeight = 30, kLegendRow = 20;
constexpr int kLinearTicks = 5;
constexpr double kTickCharWidth = 6, kTickLabelGap = 3;  // x tick labels: font-size 10, px per character

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

/// A value as a data attribute: as short as it is exact enough to read back (%g).
std::string attributeValue(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

struct Scale {
  double lo, hi;
  bool log;
  double operator()(double v) const {
    if (log) return (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    return (v - lo) / (hi - lo);
  }
};

std::pair<double, double> dataRange(const std::vector<const Panel*>& panels, bool log_y, bool y) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Panel* p : panels)
    for (const Series& s : p->series) {
      for (const auto& [px, py] : s.points) {
        const double v = y ? py : px;
        if (!std::isfinite(v) || (y && log_y && v <= 0)) continue;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      if (!y)
        for (double x : s.skipped_x) {
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
    }
  if (!std::isfinite(lo)) return log_y && y ? std::make_pair(0.1, 10.0) : std::make_pair(0.0, 1.0);
  if (y && log_y) return {std::pow(10.0, std::floor(std::log10(lo))), std::pow(10.0, std::ceil(std::log10(hi) + 1e-12))};
  if (lo == hi) return {lo - 1, hi + 1};
  if (y) return {std::min(0.0, lo), hi * 1.05};
  const double pad = 0.04 * (hi - lo);
  return {lo - pad, hi + pad};
}

/// Pixel geometry of one panel's plotting area.
struct PlotArea {
  double px, py, w, h;
};

void drawCross(std::ostringstream& out, double cx, double cy, const std::string& color) {
  out << "<path class=\"skipped\" d=\"M" << num(cx - 4) << "," << num(cy - 4) << " L" << num(cx + 4) << ","
      << num(cy + 4) << " M" << num(cx - 4) << "," << num(cy + 4) << " L" << num(cx + 4) << "," << num(cy - 4)
      << "\" stroke=\"" << color << "\" stroke-width=\"1.8\"/>\n";
}

void drawXTick(std::ostringstream& out, const PlotArea& a, double x, const std::string& label, double& last_label_right) {
  out << "<line x1=\"" << num(x) << "\" x2=\"" << num(x) << "\" y1=\"" << num(a.py + a.h) << "\" y2=\"" << num(a.py + a.h + 4)
      << "\" stroke=\"#333\"/>\n";
  // A label that would overlap the last one drawn (sizes 14 and 16 on an axis to 64) is left out;
  // its tick stays.
  const double half_width = kTickCharWidth * static_cast<double>(label.size()) / 2;
  if (x - half_width < last_label_right + kTickLabelGap) return;
  last_label_right = x + half_width;
  out << "<text x=\"" << num(x) << "\" y=\"" << num(a.py + a.h + 15) << "\" text-anchor=\"middle\" font-size=\"10\">"
      << label << "</text>\n";
}

/// The distinct x values of a panel's data: its points and its skipped sizes.
std::set<double> dataXs(const Panel& panel) {
  std::set<double> xs;
  for (const Series& s : panel.series) {
    for (const auto& p : s.points) xs.insert(p.first);
    xs.insert(s.skipped_x.begin(), s.skipped_x.end());
  }
  return xs;
}

/// Lines over a linear x axis: a polyline and dots per series, crosses on the axis for skipped sizes.
template <class X, class Y>
void drawLines(std::ostringstream& out, const Panel& panel, const PlotArea& a, const std::pair<double, double>& xr,
               const std::pair<double, double>& yr, X xpos, Y ypos) {
  // x ticks: the distinct x values of the data (problem sizes are few), else a linear spread
  std::set<double> xs = dataXs(panel);
  if (xs.size() > 12 || xs.empty()) {
    xs.clear();
    for (int i = 0; i <= kLinearTicks; ++i) xs.insert(xr.first + (xr.second - xr.first) * i / kLinearTicks);
  }
  double last_label_right = -1e9;
  for (double v : xs) drawXTick(out, a, xpos(v), tickLabel(v), last_label_right);
  for (const Series& s : panel.series) {
    out << "<g class=\"series\" data-name=\"" << escapeXml(s.name) << "\">\n";
    std::vector<std::pair<double, double>> pts;
    for (const auto& p : s.points)
      if (std::isfinite(p.second) && (!panel.log_y || p.second > 0)) pts.push_back(p);
    std::sort(pts.begin(), pts.end());
    if (pts.size() > 1) {
      out << "<polyline fill=\"none\" stroke=\"" << s.color << "\" stroke-width=\"1.8\""
          << (s.dashed ? " stroke-dasharray=\"5,3\"" : "") << " points=\"";
      for (const auto& [x, y] : pts) out << num(xpos(x)) << "," << num(ypos(std::clamp(y, yr.first, yr.second))) << " ";
      out << "\"/>\n";
    }
    for (const auto& [x, y] : pts)
      out << "<circle cx=\"" << num(xpos(x)) << "\" cy=\"" << num(ypos(std::clamp(y, yr.first, yr.second)))
          << "\" r=\"3\" fill=\"" << s.color << "\"/>\n";
    for (double x : s.skipped_x) drawCross(out, xpos(x), a.py + a.h - 6, s.color);
    out << "</g>\n";
  }
}

/// Grouped bars: one slot per distinct x (evenly spaced, labelled), one bar per series in each slot
/// in series order. A zero is a bar 2 px high (a value, not a gap); a skipped size a cross in its place.
template <class Y>
void drawBars(std::ostringstream& out, const Panel& panel, const PlotArea& a, const std::pair<double, double>& yr, Y ypos) {
  const std::set<double> xs = dataXs(panel);
  if (xs.empty()) return;
  const std::vector<double> slots(xs.begin(), xs.end());
  const double slot_width = a.w / static_cast<double>(slots.size());
  const double bar_width = 0.8 * slot_width / static_cast<double>(std::max<std::size_t>(1, panel.series.size()));
  auto slotLeft = [&](double x) {
    const auto at = std::lower_bound(slots.begin(), slots.end(), x) - slots.begin();
    return a.px + slot_width * static_cast<double>(at);
  };
  double last_label_right = -1e9;
  for (double v : slots) drawXTick(out, a, slotLeft(v) + slot_width / 2, tickLabel(v), last_label_right);
  const double base = ypos(std::max(yr.first, 0.0));
  for (std::size_t i = 0; i < panel.series.size(); ++i) {
    const Series& s = panel.series[i];
    out << "<g class=\"series\" data-name=\"" << escapeXml(s.name) << "\">\n";
    auto left = [&](double x) { return slotLeft(x) + 0.1 * slot_width + bar_width * static_cast<double>(i); };
    for (const auto& [x, y] : s.points) {
      if (!std::isfinite(y)) continue;
      const double top = std::min(ypos(std::clamp(y, yr.first, yr.second)), base - 2);
      out << "<rect class=\"bar\" data-x=\"" << attributeValue(x) << "\" data-y=\"" << attributeValue(y) << "\" x=\"" << num(left(x))
          << "\" y=\"" << num(top) << "\" width=\"" << num(bar_width) << "\" height=\"" << num(base - top)
          << "\" fill=\"" << s.color << "\" fill-opacity=\"" << (s.dashed ? "0.35" : "0.9") << "\" stroke=\"" << s.color
          << "\"/>\n";
    }
    for (double x : s.skipped_x) drawCross(out, left(x) + bar_width / 2, a.py + a.h - 6, s.color);
    out << "</g>\n";
  }
}

void drawPanel(std::ostringstream& out, const Panel& panel, double x0, double y0) {
  const PlotArea a{x0 + kLeft, y0 + kTop, kPanelWidth - kLeft - kRight, kPanelHeight - kTop - kBottom};
  const auto xr = dataRange({&panel}, false, false);
  const auto yr = panel.y_range ? *panel.y_range : dataRange({&panel}, panel.log_y, true);
  const Scale sx{xr.first, xr.second, false}, sy{yr.first, yr.second, panel.log_y};
  auto X = [&](double v) { return a.px + sx(v) * a.w; };
  auto Y = [&](double v) { return a.py + a.h - sy(v) * a.h; };
  out << "<g class=\"panel\" data-title=\"" << escapeXml(panel.title) << "\">\n";
  out << "<text x=\"" << num(a.px + a.w / 2) << "\" y=\"" << num(y0 + 18) << "\" text-anchor=\"middle\" font-size=\"13\" "
      << "font-weight=\"bold\">" << escapeXml(panel.title) << "</text>\n";
  out << "<rect x=\"" << num(a.px) << "\" y=\"" << num(a.py) << "\" width=\"" << num(a.w) << "\" height=\"" << num(a.h)
      << "\" fill=\"none\" stroke=\"#333\"/>\n";
  // y ticks and grid
  std::vector<double> yt;
  if (panel.log_y) {
    for (double d = std::round(std::log10(yr.first)); d <= std::log10(yr.second) + 1e-9; d += 1) yt.push_back(std::pow(10.0, d));
  } else {
    for (int i = 0; i <= kLinearTicks; ++i) yt.push_back(yr.first + (yr.second - yr.first) * i / kLinearTicks);
  }
  for (double v : yt) {
    out << "<line x1=\"" << num(a.px) << "\" x2=\"" << num(a.px + a.w) << "\" y1=\"" << num(Y(v)) << "\" y2=\"" << num(Y(v))
        << "\" stroke=\"#ddd\"/>\n";
    out << "<text x=\"" << num(a.px - 5) << "\" y=\"" << num(Y(v) + 4) << "\" text-anchor=\"end\" font-size=\"10\">"
        << tickLabel(v) << "</text>\n";
  }
  out << "<text class=\"x-label\" x=\"" << num(a.px + a.w / 2) << "\" y=\"" << num(a.py + a.h + 34)
      << "\" text-anchor=\"middle\" font-size=\"11\">" << escapeXml(panel.x_label) << "</text>\n";
  out << "<text class=\"y-label\" transform=\"translate(" << num(x0 + 14) << "," << num(a.py + a.h / 2)
      << ") rotate(-90)\" text-anchor=\"middle\" font-size=\"11\">" << escapeXml(panel.y_label) << "</text>\n";
  if (panel.bars) {
    drawBars(out, panel, a, yr, Y);
  } else {
    drawLines(out, panel, a, xr, yr, X, Y);
  }
  out << "</g>\n";
}
}  // namespace

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::pair<double, double> sharedRange(const std::vector<Panel>& panels, bool log_y) {
  std::vector<const Panel*> all;
  for (const Panel& p : panels) all.push_back(&p);
  return dataRange(all, log_y, true);
}

std::string renderSvg(const Figure& figure) {
  // Legend: each series name once (first color and style seen), plus the skipped marker if used.
  std::vector<const Series*> legend;
  bool any_skipped = false;
  for (const Panel& p : figure.panels)
    for (const Series& s : p.series) {
      any_skipped = any_skipped || !s.skipped_x.empty();
      if (std::none_of(legend.begin(), legend.end(), [&](const Series* l) { return l->name == s.name; }))
        legend.push_back(&s);
    }
  const std::size_t columns = std::max<std::size_t>(1, figure.panels.size());
  const double width = kPanelWidth * static_cast<double>(columns);
  const int per_row = std::max(1, static_cast<int>(width / 220));
  const int legend_rows = static_cast<int>((legend.size() + (any_skipped ? 1 : 0) + per_row - 1) / per_row);
  const double height = kTitleHeight + kPanelHeight + kLegendRow * legend_rows + 12;
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(width) << "\" height=\"" << num(height)
      << "\" viewBox=\"0 0 " << num(width) << " " << num(height) << "\" font-family=\"DejaVu Sans, sans-serif\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<text x=\"" << num(width / 2) << "\" y=\"20\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">"
      << escapeXml(figure.title) << "</text>\n";
  for (std::size_t i = 0; i < figure.panels.size(); ++i)
    drawPanel(out, figure.panels[i], kPanelWidth * static_cast<double>(i), kTitleHeight);
  out << "<g class=\"legend\">\n";
  int k = 0;
  auto slot = [&](int index) {
    return std::make_pair(10 + (index % per_row) * 220.0, kTitleHeight + kPanelHeight + 8 + (index / per_row) * kLegendRow);
  };
  const bool bars = std::all_of(figure.panels.begin(), figure.panels.end(), [](const Panel& p) { return p.bars; });
  for (const Series* s : legend) {
    const auto [lx, ly] = slot(k++);
    if (bars) {
      out << "<rect x=\"" << num(lx + 6) << "\" y=\"" << num(ly) << "\" width=\"12\" height=\"12\" fill=\"" << s->color
          << "\" fill-opacity=\"" << (s->dashed ? "0.35" : "0.9") << "\" stroke=\"" << s->color << "\"/>\n";
    } else {
      out << "<line x1=\"" << num(lx) << "\" x2=\"" << num(lx + 24) << "\" y1=\"" << num(ly + 6) << "\" y2=\"" << num(ly + 6)
          << "\" stroke=\"" << s->color << "\" stroke-width=\"2\"" << (s->dashed ? " stroke-dasharray=\"5,3\"" : "")
          << "/>\n";
    }
    out << "<text x=\"" << num(lx + 30) << "\" y=\"" << num(ly + 10) << "\" font-size=\"11\">" << escapeXml(s->name)
        << "</text>\n";
  }
  if (any_skipped) {
    const auto [lx, ly] = slot(k++);
    out << "<path d=\"M" << num(lx + 8) << "," << num(ly + 2) << " L" << num(lx + 16) << "," << num(ly + 10) << " M"
        << num(lx + 8) << "," << num(ly + 10) << " L" << num(lx + 16) << "," << num(ly + 2)
        << "\" stroke=\"#333\" stroke-width=\"1.8\"/>\n<text x=\"" << num(lx + 30) << "\" y=\"" << num(ly + 10)
        << "\" font-size=\"11\">not run (failed a smaller size on every seed)</text>\n";
  }
  out << "</g>\n</svg>\n";
  return out.str();
}

}  // namespace dash::figures
