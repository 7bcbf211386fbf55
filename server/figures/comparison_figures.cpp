#include "server/figures/comparison_figures.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "engine/core/check.h"

namespace dash::figures {

namespace {

// The dashboard's palette (web/js/palette.js): Okabe & Ito's colour-blind-safe colours, in its order.
constexpr const char* kPalette[] = {"#0072B2", "#E69F00", "#009E73", "#CC79A7",
                                    "#56B4E9", "#D55E00", "#F0E442", "#000000"};
constexpr int kPaletteSize = 8;

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Colours by group, line style by planner (the first planner seen solid, others dashed), so that
/// one planner's lines share a style and one group's lines share a colour.
struct Styles {
  explicit Styles(const FamilyData& f) {
    for (const Line& l : f.lines) {
      if (std::find(groups.begin(), groups.end(), l.group) == groups.end()) groups.push_back(l.group);
      if (std::find(planners.begin(), planners.end(), l.planner) == planners.end()) planners.push_back(l.planner);
    }
  }
  Series series(const Line& l) const {
    Series s;
    s.name = l.name();
    const auto g = std::find(groups.begin(), groups.end(), l.group) - groups.begin();
    const auto p = std::find(planners.begin(), planners.end(), l.planner) - planners.begin();
    s.color = kPalette[(groups.size() > 1 ? g : p) % kPaletteSize];
    s.dashed = p % 2 == 1;
    return s;
  }
  std::vector<std::string> groups, planners;
};

bool solved(const log::RunRecord* r) { return r->status == log::RunStatus::Solved; }

/// One series per line: the median over the solved runs of each size of `value` (NaN: skip).
std::vector<Series> medianSeries(const FamilyData& f, double (*value)(const log::RunRecord&)) {
  const Styles styles(f);
  std::vector<Series> out;
  for (const Line& l : f.lines) {
    Series s = styles.series(l);
    for (const auto& [x, runs] : l.runs) {
      std::vector<double> v;
      for (const log::RunRecord* r : runs) {
        if (!solved(r)) continue;
        const double y = value(*r);
        if (std::isfinite(y)) v.push_back(y);
      }
      if (!v.empty()) s.points.emplace_back(x, median(v));
    }
    out.push_back(std::move(s));
  }
  return out;
}

double phase(const log::RunRecord& r, std::initializer_list<log::Phase> phases) {
  if (!r.summary.phase_seconds) return std::numeric_limits<double>::quiet_NaN();
  double t = 0;
  for (log::Phase p : phases) t += (*r.summary.phase_seconds)[static_cast<int>(p)];
  return t;
}

std::string sizeLabel(const FamilyData& f) { return "problem size: " + f.x_param + " (count)"; }

std::string safeName(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return out;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  DASH_THROW_UNLESS(out.good(), "cannot write " + path);
  out << text;
  DASH_THROW_UNLESS(out.good(), "cannot write " + path);
}

}  // namespace

Figure sizeFigure(const FamilyData& f) {
  Figure fig;
  fig.title = f.family + ": representation size (medians over solved runs)";
  struct Which {
    const char* title;
    int layer;
    bool vertices;
  };
  const Which panels[] = {{"H_T vertices", 0, true}, {"H_T hyperarcs", 0, false},
                          {"H_M vertices", 2, true}, {"H_M hyperarcs", 2, false}};
  const Styles styles(f);
  for (const Which& w : panels) {
    Panel p;
    p.title = w.title;
    p.x_label = sizeLabel(f);
    p.y_label = std::string(w.vertices ? "vertices" : "hyperarcs") + " (count, log scale)";
    p.log_y = true;
    for (const Line& l : f.lines) {
      Series s = styles.series(l);
      for (const auto& [x, runs] : l.runs) {
        std::vector<double> v;
        for (const log::RunRecord* r : runs)
          if (solved(r) && r->summary.sizes)
            v.push_back(static_cast<double>(w.vertices ? r->summary.sizes->vertices[w.layer]
                                                       : r->summary.sizes->hyperarcs[w.layer]));
        if (!v.empty()) s.points.emplace_back(x, median(v));
      }
      p.series.push_back(std::move(s));
    }
    fig.panels.push_back(std::move(p));
  }
  return fig;
}

Figure timeFigure(const FamilyData& f) {
  using P = log::Phase;
  Figure fig;
  fig.title = f.family + ": planning time (medians over solved runs)";
  struct Which {
    const char* title;
    double (*value)(const log::RunRecord&);
  };
  const Which panels[] = {
      {"construction (task + motion)",
       [](const log::RunRecord& r) { return phase(r, {P::TaskConstruction, P::MotionConstruction}); }},
      {"query (task + motion)",
       [](const log::RunRecord& r) { return phase(r, {P::TaskQuery, P::TaskConflictDetection, P::MotionQuery}); }},
      {"conflict resolution", [](const log::RunRecord& r) { return phase(r, {P::ConflictResolution}); }},
      {"total", [](const log::RunRecord& r) {
         return r.summary.total_time ? *r.summary.total_time : std::numeric_limits<double>::quiet_NaN();
       }}};
  for (const Which& w : panels) {
    Panel p;
    p.title = w.title;
    p.x_label = sizeLabel(f);
    p.y_label = "time (s, log scale)";
    p.log_y = true;
    p.series = medianSeries(f, w.value);
    fig.panels.push_back(std::move(p));
  }
  const auto range = sharedRange(fig.panels, true);  // the paper: one y range per family
  for (Panel& p : fig.panels) p.y_range = range;
  return fig;
}

Figure successFigure(const FamilyData& f) {
  Figure fig;
  fig.title = f.family + ": success rate";
  Panel p;
  p.title = "solved runs";
  p.x_label = sizeLabel(f);
  p.y_label = "solved / finished runs (%)";
  p.y_range = std::make_pair(0.0, 100.0);
  p.bars = true;  // rates often coincide (100 %): side by side, none hides another
  const Styles styles(f);
  for (const Line& l : f.lines) {
    Series s = styles.series(l);
    for (const auto& [x, runs] : l.runs) {
      if (runs.empty()) continue;
      const auto n = std::count_if(runs.begin(), runs.end(), solved);
      s.points.emplace_back(x, 100.0 * static_cast<double>(n) / static_cast<double>(runs.size()));
    }
    for (const auto& [x, count] : l.skipped)
      if (count > 0 && !l.runs.count(x)) s.skipped_x.push_back(x);
    p.series.push_back(std::move(s));
  }
  fig.panels.push_back(std::move(p));
  return fig;
}

void convertToPng(const std::string& rsvg_convert, const std::string& svg, const std::string& png) {
  const pid_t pid = fork();
  DASH_THROW_UNLESS(pid >= 0, std::string("cannot start rsvg-convert: ") + std::strerror(errno));
  if (pid == 0) {
    execlp(rsvg_convert.c_str(), rsvg_convert.c_str(), "-f", "png", "-o", png.c_str(), svg.c_str(),
           static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  DASH_THROW_UNLESS(WIFEXITED(status) && WEXITSTATUS(status) == 0,
                    "rsvg-convert failed on " + svg + (WIFEXITED(status) && WEXITSTATUS(status) == 127
                                                           ? " (not installed? Debian package librsvg2-bin)"
                                                           : ""));
}

FigureFiles writeComparisonFigures(const log::ResultsDb& db, const FigureOptions& options) {
  DASH_THROW_UNLESS(!options.dir.empty(), "--figures needs a directory");
  std::error_code ec;
  std::filesystem::create_directories(options.dir, ec);
  DASH_THROW_UNLESS(!ec && std::filesystem::is_directory(options.dir), "cannot create " + options.dir);
  const FigureRuns runs = collectFigureRuns(db, options.batch_id);
  DASH_THROW_UNLESS(!runs.families.empty(), options.batch_id.empty()
                                                ? std::string("no finished runs to plot")
                                                : "no finished runs to plot in batch " + options.batch_id);
  FigureFiles out;
  for (const FamilyData& f : runs.families) {
    out.families.push_back(f.family);
    const std::pair<const char*, Figure> figures[] = {
        {"sizes", sizeFigure(f)}, {"time", timeFigure(f)}, {"success", successFigure(f)}};
    for (const auto& [what, figure] : figures) {
      const std::string base = (std::filesystem::path(options.dir) / (safeName(f.family) + "-" + what)).string();
      writeFile(base + ".svg", renderSvg(figure));
      out.files.push_back(base + ".svg");
      if (options.png) {
        convertToPng(options.rsvg_convert, base + ".svg", base + ".png");
        out.files.push_back(base + ".png");
      }
    }
  }
  return out;
}

}  // namespace dash::figures
