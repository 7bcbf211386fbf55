#include "engine/planners/progress_sink.h"

#include <algorithm>
#include <chrono>
#include <variant>

namespace dash {

ProgressSink::~ProgressSink() { stopTicker(); }

void ProgressSink::onEvent(const log::Event& event) {
  std::lock_guard<std::mutex> lock(mutex_);
  iteration_ = event.iteration;
  if (const auto* r = std::get_if<log::RepresentationEvent>(&event.payload)) {
    auto& n = counts_[static_cast<int>(r->layer)][static_cast<int>(r->kind)];
    n = r->change == log::ElementChange::Added ? n + 1 : (n > 0 ? n - 1 : 0);
  } else if (const auto* p = std::get_if<log::PhaseEvent>(&event.payload)) {
    if (p->boundary == log::PhaseBoundary::Start) {
      phase_ = p->phase;
      phase_started_ = clock_.seconds();
    }
  } else if (const auto* c = std::get_if<log::ConstraintEvent>(&event.payload)) {
    ++constraints_;
    if (verbose_)
      std::fprintf(out_, "  + %s constraint %s: %s\n", log::toString(c->kind), c->content.c_str(), c->conflict.c_str());
  } else if (const auto* x = std::get_if<log::TaskSpaceExpansionEvent>(&event.payload)) {
    if (verbose_) std::fprintf(out_, "  + task space expansion: %s (%s)\n", x->added.c_str(), x->reason.c_str());
  } else if (const auto* w = std::get_if<log::ProgressEvent>(&event.payload)) {
    work_ = *w;
    working_ = true;
    if (w->current.empty()) {
      // The work ended: its last figures at once if a line showed it running, then no more.
      if (shown_ || clock_.seconds() - last_print_ >= period_) print();
      working_ = false;
      shown_ = false;
      return;
    }
  }
  if (clock_.seconds() - last_print_ >= period_) print();
}

void ProgressSink::flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  print();
}

void ProgressSink::startTicker(double quiet_seconds) {
  stopTicker();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ticker_stop_ = false;
  }
  ticker_ = std::thread([this, quiet_seconds] {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto wake = std::chrono::duration<double>(std::min(0.25, quiet_seconds / 4));
    while (!ticker_cv_.wait_for(lock, wake, [&] { return ticker_stop_; })) {
      if (clock_.seconds() - last_print_ >= quiet_seconds) print();
    }
  });
}

void ProgressSink::stopTicker() {
  if (!ticker_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ticker_stop_ = true;
  }
  ticker_cv_.notify_all();
  ticker_.join();
}

std::string ProgressSink::formatWork(const log::ProgressEvent& p) {
  if (p.phase != log::Phase::ConflictResolution) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s %lld/%lld", log::toString(p.phase), static_cast<long long>(p.done),
                  static_cast<long long>(p.total));
    return buf;
  }
  char buf[96];
  std::snprintf(buf, sizeof buf, "steps %lld/%lld", static_cast<long long>(p.done), static_cast<long long>(p.total));
  std::string out = buf;
  if (!p.current.empty()) out += " (" + p.current + ")";
  std::snprintf(buf, sizeof buf, " %.1f steps/s", p.rate);
  return out + buf;
}

std::string ProgressSink::formatLayer(const char* name, std::size_t vertices, std::size_t hyperarcs, bool building) {
  // A layer still empty while its construction phase runs (DaSH builds H_M whole, then reports it):
  // "building", not a 0/0 that reads as stuck.
  if (building && vertices == 0 && hyperarcs == 0) return std::string(name) + " building";
  return std::string(name) + " " + std::to_string(vertices) + "/" + std::to_string(hyperarcs);
}

void ProgressSink::print() {
  last_print_ = clock_.seconds();
  const std::string work = working_ ? "  " + formatWork(work_) : std::string();
  shown_ = shown_ || working_;
  char phase[64];
  std::snprintf(phase, sizeof phase, "%s %.1fs", log::toString(phase_), last_print_ - phase_started_);
  const bool task = phase_ == log::Phase::TaskConstruction, motion = phase_ == log::Phase::MotionConstruction;
  std::fprintf(out_, "[%7.2fs] iter %-3d %-30s %s  %s  %s  %s  constraints %zu%s\n", last_print_, iteration_, phase,
               formatLayer("H_T", counts_[0][0], counts_[0][1], task).c_str(),
               formatLayer("H_TE", counts_[1][0], counts_[1][1], false).c_str(),
               formatLayer("H_M", counts_[2][0], counts_[2][1], motion).c_str(),
               formatLayer("H_ME", counts_[3][0], counts_[3][1], false).c_str(), constraints_, work.c_str());
  std::fflush(out_);
}

}  // namespace dash
