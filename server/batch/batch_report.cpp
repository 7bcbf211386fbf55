#include "server/batch/batch_report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "engine/scenarios/scenario_registry.h"
#include "server/figures/paired_stats.h"
#include "server/batch/batch_store.h"
#include "server/batch/run_process.h"

namespace dash::batch {
namespace {

using log::RunStatus;

/// A text table: first `left` columns left-aligned, the rest right-aligned.
class Table {
 public:
  Table(std::vector<std::string> header, std::size_t left) : left_(left) { rows_.push_back(std::move(header)); }
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  std::string str() const {
    std::vector<std::size_t> width(rows_.front().size(), 0);
    for (const auto& r : rows_) {
      for (std::size_t i = 0; i < r.size(); ++i) width[i] = std::max(width[i], r[i].size());
    }
    std::ostringstream out;
    for (const auto& r : rows_) {
      std::string line;
      for (std::size_t i = 0; i < r.size(); ++i) {
        const std::string pad(width[i] - r[i].size(), ' ');
        line += (i == 0 ? "" : "  ") + (i < left_ ? r[i] + pad : pad + r[i]);
      }
      while (!line.empty() && line.back() == ' ') line.pop_back();
      out << "  " << line << "\n";
    }
    return out.str();
  }

 private:
  std::vector<std::vector<std::string>> rows_;
  std::size_t left_;
};

std::string fmtCount(double v) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, v == std::floor(v) ? "%.0f" : "%.1f", v);
  return buf;
}

std::string fmtSeconds(double v) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 10 ? "%.3f" : v < 100 ? "%.2f" : "%.1f", v);
  return buf;
}

struct Row {
  std::vector<int> param_values;  ///< family order, for sorting
  std::string params_text;
  std::string planner;
  int planner_order = 0;
  std::vector<const log::RunRecord*> runs;  ///< finished runs (not running, not cancelled)
};

bool finishedStatus(RunStatus s) { return s != RunStatus::Running && s != RunStatus::Cancelled; }

/// One line of a stop axis (family, the other parameters, planner label): per size of the axis, its
/// seeds, those with a final result, those solved, those the axis stop rule skipped.
struct AxisLine {
  std::string others;  ///< the other parameters, "robots=8 walls=2"
  std::string axis;
  struct Size {
    int seeds = 0, finished = 0, solved = 0, skipped = 0;
  };
  std::map<int, Size> sizes;
};

/// A line's key: its other parameters' values (numeric order) and the planner label.
using AxisLineKey = std::pair<std::vector<int>, std::string>;

void addToAxisLine(const StoredRun& r, std::map<std::string, std::map<AxisLineKey, AxisLine>>& lines) {
  if (r.spec.stop_axis.empty()) return;
  std::string others;
  std::vector<int> values;
  int value = 0;
  for (const auto& [name, v] : r.spec.params) {
    if (name == r.spec.stop_axis) {
      value = v;
      continue;
    }
    others += (others.empty() ? "" : " ") + name + "=" + std::to_string(v);
    values.push_back(v);
  }
  AxisLine& line = lines[r.spec.family][{values, r.spec.label}];
  line.others = others;
  line.axis = r.spec.stop_axis;
  AxisLine::Size& size = line.sizes[value];
  ++size.seeds;
  if (r.complete()) ++size.finished;
  if (r.status && *r.status == "solved") ++size.solved;
  if (!r.skipped.empty()) ++size.skipped;
}

// Where each planner breaks: along each stop axis, the largest size every seed solved, the largest
// some seed solved, the first size no seed solved, the first size skipped, the sizes still open, and
// every finished size some seed failed (a failure below the largest size solved is a hole the first
// two columns do not show).
std::string formatAxisLines(const std::map<AxisLineKey, AxisLine>& lines) {
  Table table({"line", "planner", "axis", "all seeds solved up to", "some seed up to", "none solved at",
               "skipped from", "sizes open", "failed (size: solved/seeds)"},
              3);
  auto text = [](std::optional<int> v) { return v ? std::to_string(*v) : std::string("-"); };
  for (const auto& [key, line] : lines) {
    std::optional<int> all, some, none, skip;
    int open = 0;
    std::string failed;
    for (const auto& [value, size] : line.sizes) {
      if (size.skipped > 0) {
        if (!skip) skip = value;
        continue;
      }
      if (size.finished < size.seeds) {
        ++open;
        continue;
      }
      if (size.solved == size.seeds) all = value;
      if (size.solved > 0) some = value;
      if (size.solved == 0 && !none) none = value;
      if (size.solved < size.seeds)
        failed += (failed.empty() ? "" : ", ") + std::to_string(value) + ": " + std::to_string(size.solved) + "/" +
                  std::to_string(size.seeds);
    }
    table.add({line.others.empty() ? "-" : line.others, key.second, line.axis, text(all), text(some), text(none), text(skip),
               std::to_string(open), failed.empty() ? "-" : failed});
  }
  return "Where each planner breaks (along the stop axis; sizes with every seed finished)\n" + table.str() + "\n";
}

std::string fmtPercent(std::optional<double> v) {
  if (!v) return "-";
  char buf[16];
  std::snprintf(buf, sizeof buf, "%.0f%%", 100 * *v);
  return buf;
}

std::string fmtInterval(const figures::RateInterval& r) {
  return r.rate ? "[" + fmtPercent(r.low) + ", " + fmtPercent(r.high) + "]" : "-";
}

/// Three significant digits, without an exponent from 0.001 up ("1130", not "1.13e+03").
std::string fmtRatio(std::optional<double> v) {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, *v >= 1000 ? "%.0f" : *v >= 0.001 ? "%.3g" : "%.2e", *v);
  return buf;
}

/// One row of the paired table: `a` and `b` are the two planners' runs of some scenes, by seed.
void addPairedRow(Table& table, const std::string& params, const std::string& a, const std::string& b,
                  const std::vector<std::pair<figures::Observation, figures::Observation>>& pairs) {
  const figures::PairedStats s = figures::pairedStats(pairs);
  std::string p = "-";
  if (s.p_value) p = *s.p_value < 0.001 ? "<0.001" : fmtRatio(s.p_value);
  const std::string ci = s.ratio_low ? "[" + fmtRatio(s.ratio_low) + ", " + fmtRatio(s.ratio_high) + "]" : "-";
  auto rate = [&](int solved, const figures::RateInterval& r) {
    return std::to_string(solved) + "/" + std::to_string(s.pairs) + " " + fmtInterval(r);
  };
  table.add({params, a + " / " + b, std::to_string(s.pairs), std::to_string(s.both_solved), fmtRatio(s.ratio), ci,
             std::to_string(s.a_faster), std::to_string(s.b_faster), std::to_string(s.undecided), p,
             rate(s.a_solved, s.a_success), rate(s.b_solved, s.b_success)});
}

// Every two planner configurations of a family on the same scenes and seeds (paired_stats.h): per
// parameters and over all of them. A scene's run of a configuration is its first finished one.
std::string formatPaired(const std::vector<const Row*>& rows) {
  std::map<int, std::string> by_order;  // the report's planner order
  std::vector<std::string> params;       // in the rows' order
  std::map<std::string, std::map<std::string, std::map<std::uint64_t, const log::RunRecord*>>> runs;
  for (const Row* row : rows) {
    by_order.emplace(row->planner_order, row->planner);
    if (std::find(params.begin(), params.end(), row->params_text) == params.end()) params.push_back(row->params_text);
    auto& by_seed = runs[row->params_text][row->planner];
    for (const log::RunRecord* r : row->runs) by_seed.try_emplace(r->meta.seed, r);
  }
  std::vector<std::string> planners;
  for (const auto& [order, name] : by_order) planners.push_back(name);
  Table table({"params", "a / b", "pairs", "both solved", "time ratio a/b", "95% CI", "a faster", "b faster",
               "undecided", "sign test p", "a solved [95% CI]", "b solved [95% CI]"},
              2);
  bool any = false;
  for (std::size_t i = 0; i < planners.size(); ++i) {
    for (std::size_t j = i + 1; j < planners.size(); ++j) {
      std::vector<std::pair<figures::Observation, figures::Observation>> all;
      for (const std::string& p : params) {
        std::vector<std::pair<figures::Observation, figures::Observation>> pairs;
        const auto& a = runs[p][planners[i]];
        const auto& b = runs[p][planners[j]];
        for (const auto& [seed, run] : a)
          if (b.count(seed)) pairs.emplace_back(figures::observe(*run), figures::observe(*b.at(seed)));
        if (pairs.empty()) continue;
        addPairedRow(table, p.empty() ? "-" : p, planners[i], planners[j], pairs);
        all.insert(all.end(), pairs.begin(), pairs.end());
      }
      if (!all.empty()) addPairedRow(table, "all", planners[i], planners[j], all);
      any = any || !all.empty();
    }
  }
  if (!any) return "";
  return "Paired comparison (same scenes and seeds; time ratio: geometric mean of a/b over the pairs both solved,\n"
         "95% t interval on the log ratios; sign test: two-sided exact, Gehan's pair scores, a run that did not\n"
         "solve censored at its time limit; success: 95% Wilson interval)\n" +
         table.str() + "\n";
}

/// A row's parameters from a run's stored JSON, in the family's order (the stored JSON object is sorted
/// by name); an unknown family's in the stored order.
Row paramsRow(const std::string& family, const std::string& params_json) {
  const nlohmann::json params = nlohmann::json::parse(params_json, nullptr, false);
  std::vector<std::pair<std::string, int>> ordered;
  if (const ScenarioFamily* f = findScenarioFamily(family)) {
    for (const ParamSpec& p : f->params) {
      if (params.is_object() && params.contains(p.name) && params[p.name].is_number_integer()) {
        ordered.emplace_back(p.name, params[p.name].get<int>());
      }
    }
  } else if (params.is_object()) {
    for (const auto& [k, v] : params.items()) ordered.emplace_back(k, v.is_number_integer() ? v.get<int>() : 0);
  }
  Row row;
  for (const auto& [k, v] : ordered) {
    row.param_values.push_back(v);
    row.params_text += (row.params_text.empty() ? "" : " ") + k + "=" + std::to_string(v);
  }
  return row;
}

/// Runs the axis stop rule skipped (axis_stop.h), per (params, planner): count, reason and the first
/// ordinal (the spec's order, so sizes read 4, 8, 16 rather than 16, 4, 8).
struct Skipped {
  int runs = 0;
  std::string why;
  int first_ordinal = 0;
};

// One formatReport, its steps as methods: group the finished runs by family and row (parameters,
// planner), add what the batch's store knows (skipped runs, stop axis lines), then per family its tables.
class ReportWriter {
 public:
  ReportWriter(const log::ResultsDb& db, const ReportOptions& options) : db_(db), options_(options) {}

  std::string run() {
    log::RunFilter filter;
    filter.batch_id = options_.batch_id;
    filter.limit = std::numeric_limits<std::int32_t>::max();
    filter.newest_first = false;
    runs_ = db_.listRuns(filter);
    for (const log::RunRecord& r : runs_)
      if (finishedStatus(r.status)) addRun(r);
    if (!options_.batch_id.empty()) addStoredRuns();
    if (family_order_.empty()) {
      return options_.batch_id.empty() ? "no finished runs\n" : "no finished runs in batch " + options_.batch_id + "\n";
    }
    std::ostringstream out;
    for (const std::string& family : orderedFamilies()) out << formatFamily(family);
    return out.str();
  }

 private:
  void addRun(const log::RunRecord& r) {
    const std::string& family = r.meta.family;
    if (!families_.count(family)) family_order_.push_back(family);
    const std::string planner = r.meta.planner_config_name.empty() ? r.meta.planner : r.meta.planner_config_name;
    planner_order_.emplace(planner, static_cast<int>(planner_order_.size()));
    const Row row = paramsRow(family, r.meta.params_json);
    const std::string key = row.params_text + "\n" + planner;
    Row& slot = families_[family].try_emplace(key, row).first->second;
    slot.planner = planner;
    slot.planner_order = planner_order_[planner];
    slot.runs.push_back(&r);
  }

  void addStoredRuns() {
    const BatchStore store(db_.path(), log::OpenMode::ReadOnly);
    for (const StoredRun& r : store.runs(options_.batch_id)) {
      addToAxisLine(r, axis_lines_);
      if (r.skipped.empty()) continue;
      if (!families_.count(r.spec.family) && !skipped_.count(r.spec.family)) family_order_.push_back(r.spec.family);
      auto& slot = skipped_[r.spec.family][{r.spec.paramsText(), r.spec.label}];
      if (slot.runs++ == 0) slot.first_ordinal = r.spec.ordinal;  // runs() comes in ordinal order
      slot.why = r.skipped;
    }
  }

  // Families in the registry's order, unknown ones after.
  std::vector<std::string> orderedFamilies() const {
    std::vector<std::string> ordered;
    for (const auto& f : scenarioFamilies()) {
      if (families_.count(f.name) || skipped_.count(f.name)) ordered.push_back(f.name);
    }
    for (const auto& f : family_order_) {
      if (!findScenarioFamily(f)) ordered.push_back(f);
    }
    return ordered;
  }

  std::string formatFamily(const std::string& family) {
    std::vector<const Row*> rows;
    for (const auto& [key, row] : families_[family]) rows.push_back(&row);
    std::sort(rows.begin(), rows.end(), [](const Row* a, const Row* b) {
      if (a->param_values != b->param_values) return a->param_values < b->param_values;
      return a->planner_order < b->planner_order;
    });
    std::size_t count = 0;
    for (const Row* r : rows) count += r->runs.size();
    const char* basis = options_.include_unsolved ? "finished runs" : "solved runs";
    std::ostringstream out;
    out << "== " << family << " (" << count << " finished runs; medians across seeds over " << basis << ") ==\n\n";
    out << "Representation sizes (vertices V, hyperarcs A)\n" << sizesTable(rows) << "\n";
    out << "Time breakdown (s, phase totals)\n" << timesTable(rows) << "\n";
    out << "Success rate\n" << successTable(rows) << "\n";
    out << formatPaired(rows);
    if (skipped_.count(family)) out << "Skipped by the axis stop rule (not run)\n" << skippedTable(family) << "\n";
    if (axis_lines_.count(family)) out << formatAxisLines(axis_lines_[family]);
    return out.str();
  }

  // The runs of a row the medians are over.
  std::vector<const log::RunRecord*> basisRuns(const Row& row) const {
    std::vector<const log::RunRecord*> v;
    for (const auto* r : row.runs) {
      if (r->status == RunStatus::Solved ||
          (options_.include_unsolved && (r->status == RunStatus::Timeout || r->status == RunStatus::Infeasible))) {
        v.push_back(r);
      }
    }
    return v;
  }

  std::string sizesTable(const std::vector<const Row*>& rows) const {
    Table sizes({"params", "planner", "n", "H_T V", "H_T A", "H_TE V", "H_TE A", "H_M V", "H_M A", "H_ME V", "H_ME A"},
                2);
    for (const Row* row : rows) {
      const auto basis_runs = basisRuns(*row);
      std::vector<std::string> cells = {row->params_text, row->planner, std::to_string(basis_runs.size())};
      for (int layer = 0; layer < log::kLayerCount; ++layer) {
        std::vector<double> v, a;
        for (const auto* r : basis_runs) {
          if (!r->summary.sizes) continue;
          v.push_back(static_cast<double>(r->summary.sizes->vertices[layer]));
          a.push_back(static_cast<double>(r->summary.sizes->hyperarcs[layer]));
        }
        cells.push_back(fmtCount(median(v)));
        cells.push_back(fmtCount(median(a)));
      }
      sizes.add(cells);
    }
    return sizes.str();
  }

  // Phase indices: TaskConstruction, TaskQuery, TaskConflictDetection, MotionConstruction,
  // MotionQuery, ConflictResolution.
  std::string timesTable(const std::vector<const Row*>& rows) const {
    Table times({"params", "planner", "n", "task constr", "task query", "task conflicts", "motion constr",
                 "motion query", "conflict res", "total"},
                2);
    for (const Row* row : rows) {
      const auto basis_runs = basisRuns(*row);
      std::vector<std::string> cells = {row->params_text, row->planner, std::to_string(basis_runs.size())};
      for (int phase = 0; phase < 6; ++phase) {
        std::vector<double> v;
        for (const auto* r : basis_runs) {
          if (r->summary.phase_seconds) v.push_back((*r->summary.phase_seconds)[phase]);
        }
        cells.push_back(fmtSeconds(median(v)));
      }
      std::vector<double> total;
      for (const auto* r : basis_runs) {
        if (r->summary.total_time) total.push_back(*r->summary.total_time);
      }
      cells.push_back(fmtSeconds(median(total)));
      times.add(cells);
    }
    return times.str();
  }

  // A run stopped by its memory limit is stored as crashed with an error that says so (run_process.cpp);
  // it is counted apart: out of memory is an outcome, a crash a defect.
  static std::string successTable(const std::vector<const Row*>& rows) {
    Table success({"params", "planner", "runs", "solved", "timeout", "infeasible", "out of memory", "crashed", "success",
                   "95% CI (Wilson)"},
                  2);
    for (const Row* row : rows) {
      int solved = 0, timeout = 0, infeasible = 0, out_of_memory = 0, crashed = 0;
      for (const auto* r : row->runs) {
        const bool oom = r->status == RunStatus::Crashed && r->summary.error.rfind(kOutOfMemoryError, 0) == 0;
        solved += r->status == RunStatus::Solved;
        timeout += r->status == RunStatus::Timeout;
        infeasible += r->status == RunStatus::Infeasible;
        out_of_memory += oom;
        crashed += r->status == RunStatus::Crashed && !oom;
      }
      const std::size_t n = row->runs.size();
      char rate[16];
      std::snprintf(rate, sizeof rate, "%.0f%%", n > 0 ? 100.0 * solved / static_cast<double>(n) : 0.0);
      success.add({row->params_text, row->planner, std::to_string(n), std::to_string(solved), std::to_string(timeout),
                   std::to_string(infeasible), std::to_string(out_of_memory), std::to_string(crashed), rate,
                   fmtInterval(figures::wilson(solved, static_cast<int>(n)))});
    }
    return success.str();
  }

  std::string skippedTable(const std::string& family) {
    std::vector<std::pair<const std::pair<std::string, std::string>*, const Skipped*>> in_spec_order;
    for (const auto& [key, value] : skipped_[family]) in_spec_order.emplace_back(&key, &value);
    std::sort(in_spec_order.begin(), in_spec_order.end(),
              [](const auto& a, const auto& b) { return a.second->first_ordinal < b.second->first_ordinal; });
    Table skips({"params", "planner", "runs", "why"}, 4);
    for (const auto& [key, value] : in_spec_order)
      skips.add({key->first, key->second, std::to_string(value->runs), value->why});
    return skips.str();
  }

  const log::ResultsDb& db_;
  const ReportOptions& options_;
  std::vector<log::RunRecord> runs_;  ///< the rows point into it
  std::map<std::string, int> planner_order_;
  std::map<std::string, std::map<std::string, Row>> families_;  // family -> row key -> row
  std::vector<std::string> family_order_;
  std::map<std::string, std::map<std::pair<std::string, std::string>, Skipped>> skipped_;
  std::map<std::string, std::map<AxisLineKey, AxisLine>> axis_lines_;  // family -> line
};

}  // namespace

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string formatReport(const log::ResultsDb& db, const ReportOptions& options) {
  return ReportWriter(db, options).run();
}

}  // namespace dash::batch
