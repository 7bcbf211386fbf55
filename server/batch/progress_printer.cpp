#include "server/batch/progress_printer.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace dash::batch {

namespace {

/// "motion construction" for log::Phase::MotionConstruction.
std::string phaseWords(log::Phase phase) {
  std::string words = log::toString(phase);
  for (char& c : words)
    if (c == '_') c = ' ';
  return words;
}

constexpr double kQuietRunLineSeconds = 10.0;  // lines mode: a run without reported progress, this often
constexpr double kWorkLineSeconds = 2.0;       // lines mode: a run reporting a long phase's progress
constexpr double kBarRunSeconds = 5.0;         // bar: the longest-running run shown from this age
constexpr std::size_t kBarKeyChars = 48;       // bar: a longer run key keeps its end
}  // namespace

double SteadyEta::operator()(const BatchProgress& p) {
  if (p.done != done_ || (eta_ < 0 && p.eta >= 0)) {
    done_ = p.done;
    eta_ = p.eta;
    at_ = p.elapsed;
  }
  if (eta_ < 0 || p.remaining <= 0) return eta_ < 0 ? -1.0 : 0.0;
  const double left = eta_ - (p.elapsed - at_);
  return left > 0 ? left : -1.0;
}

ProgressPrinter::Mode ProgressPrinter::autoMode(std::FILE* out, bool quiet) {
  if (quiet) return Mode::kQuiet;
  return isatty(fileno(out)) ? Mode::kBar : Mode::kLines;
}

std::string ProgressPrinter::formatDuration(double seconds) {
  if (!(seconds >= 0) || !std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%lds", s);
  }
  return buf;
}

std::string ProgressPrinter::formatBar(const BatchProgress& p, int width) {
  const double fraction = p.total > 0 ? static_cast<double>(p.done) / static_cast<double>(p.total) : 1.0;
  const int filled = std::clamp(static_cast<int>(std::floor(fraction * width)), 0, width);
  std::string bar = "[" + std::string(static_cast<std::size_t>(filled), '#') +
                    std::string(static_cast<std::size_t>(width - filled), '.') + "] ";
  char buf[256];
  std::snprintf(buf, sizeof buf, "%lld/%lld done  %lld failed  %lld running  %lld left", static_cast<long long>(p.done),
                static_cast<long long>(p.total), static_cast<long long>(p.failed), static_cast<long long>(p.running),
                static_cast<long long>(p.remaining));
  bar += buf;
  if (p.crashed > 0) bar += "  (" + std::to_string(p.crashed) + " crashed)";
  if (p.cancelling) {
    bar += "  cancelling...";
  } else {
    bar += "  ETA " + (p.eta >= 0 ? formatDuration(p.eta) : std::string("?"));
  }
  // The running runs that are scheduling: how far each has got (steps scheduled of the plan's).
  std::string work;
  for (const ActiveRun& a : p.active) {
    if (!a.work || a.work->current.empty()) continue;
    work += (work.empty() ? "  | steps " : ", ") + std::to_string(a.work->done) + "/" + std::to_string(a.work->total);
  }
  // Otherwise the run that has been running longest (the list is oldest first), once it is not quick.
  if (work.empty() && !p.active.empty() && p.active.front().seconds >= kBarRunSeconds) {
    const ActiveRun& a = p.active.front();
    const std::string key = a.key.size() > kBarKeyChars ? "..." + a.key.substr(a.key.size() - kBarKeyChars) : a.key;
    const std::string phase = formatWork(a);
    work = "  | " + key + " " + (phase.empty() ? "" : phase + " ") + formatDuration(a.seconds);
  }
  return bar + work;
}

std::string ProgressPrinter::formatWork(const ActiveRun& run) {
  // Without progress of a long phase, the phase it is in (a DaSH construction, a task layer), if any.
  if (!run.work || run.work->current.empty())
    return run.phase && *run.phase != log::Phase::Other ? std::string("in ") + phaseWords(*run.phase) : "";
  const log::ProgressEvent& w = *run.work;
  char buf[160];
  if (w.phase == log::Phase::ConflictResolution) {
    std::snprintf(buf, sizeof buf, "steps %lld/%lld (%s) %.1f steps/s", static_cast<long long>(w.done),
                  static_cast<long long>(w.total), w.current.c_str(), w.rate);
  } else {
    std::snprintf(buf, sizeof buf, "%s %lld/%lld (%s)", log::toString(w.phase), static_cast<long long>(w.done),
                  static_cast<long long>(w.total), w.current.c_str());
  }
  return buf;
}

std::string ProgressPrinter::formatActiveLine(const ActiveRun& run) {
  const std::string work = formatWork(run);
  return "[running]  " + run.key + "  " + (work.empty() ? "" : work + "  ") + formatDuration(run.seconds);
}

std::string ProgressPrinter::formatLine(const BatchProgress& p, const FinishedRun& run) {
  char head[64];
  std::snprintf(head, sizeof head, "[%lld/%lld] %-10s ", static_cast<long long>(p.done),
                static_cast<long long>(p.total), log::toString(run.status));
  char tail[32];
  std::snprintf(tail, sizeof tail, "  %.1f s", run.seconds);
  std::string line = head + run.key + tail;
  if (!run.error.empty() && run.status != log::RunStatus::Solved) {
    std::string error = run.error;
    std::replace(error.begin(), error.end(), '\n', ' ');
    if (error.size() > 160) error = error.substr(0, 157) + "...";
    line += "  (" + error + ")";
  }
  return line;
}

void ProgressPrinter::operator()(const BatchProgress& progress) {
  BatchProgress p = progress;
  p.eta = eta_(progress);
  switch (mode_) {
    case Mode::kQuiet:
      return;
    case Mode::kLines: {
      if (p.finished) std::fprintf(out_, "%s\n", formatLine(p, *p.finished).c_str());
      std::map<std::string, double> printed;
      for (const ActiveRun& a : p.active) {
        const auto last = active_printed_.find(a.uuid);
        double at = last == active_printed_.end() ? -1e9 : last->second;
        const bool working = !formatWork(a).empty();
        // A run reporting progress every 2 s; one that reports none (a DaSH construction) every
        // 10 s once it has run 10 s, so that a long run never leaves the log silent.
        if ((working && p.elapsed - at >= kWorkLineSeconds) ||
            (!working && a.seconds >= kQuietRunLineSeconds && p.elapsed - at >= kQuietRunLineSeconds)) {
          std::fprintf(out_, "%s\n", formatActiveLine(a).c_str());
          at = p.elapsed;
        }
        printed[a.uuid] = at;
      }
      active_printed_ = std::move(printed);
      std::fflush(out_);
      return;
    }
    case Mode::kBar:
      if (p.finished && p.finished->status == log::RunStatus::Crashed) {
        std::fprintf(out_, "\r\033[K%s\n", formatLine(p, *p.finished).c_str());
      }
      std::fprintf(out_, "\r\033[K%s", formatBar(p).c_str());
      std::fflush(out_);
      bar_drawn_ = true;
      return;
  }
}

void ProgressPrinter::finish() {
  if (mode_ == Mode::kBar && bar_drawn_) {
    std::fprintf(out_, "\n");
    std::fflush(out_);
  }
}

}  // namespace dash::batch
