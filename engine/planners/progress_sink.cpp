#include "engine/planners/progress_sink.h"

#include <variant>

namespace dash {

void ProgressSink::onEvent(const log::Event& event) {
  std::lock_guard<std::mutex> lock(mutex_);
  iteration_ = event.iteration;
  if (const auto* r = std::get_if<log::RepresentationEvent>(&event.payload)) {
    auto& n = counts_[static_cast<int>(r->layer)][static_cast<int>(r->kind)];
    n = r->change == log::ElementChange::Added ? n + 1 : (n > 0 ? n - 1 : 0);
  } else if (const auto* p = std::get_if<log::PhaseEvent>(&event.payload)) {
    if (p->boundary == log::PhaseBoundary::Start) phase_ = p->phase;
  } else if (const auto* c = std::get_if<log::ConstraintEvent>(&event.payload)) {
    ++constraints_;
    if (verbose_)
      std::fprintf(out_, "  + %s constraint %s: %s\n", log::toString(c->kind), c->content.c_str(), c->conflict.c_str());
  } else if (const auto* x = std::get_if<log::TaskSpaceExpansionEvent>(&event.payload)) {
    if (verbose_) std::fprintf(out_, "  + task space expansion: %s (%s)\n", x->added.c_str(), x->reason.c_str());
  }
  if (clock_.seconds() - last_print_ >= period_) print();
}

void ProgressSink::flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  print();
}

void ProgressSink::print() {
  last_print_ = clock_.seconds();
  std::fprintf(out_,
               "[%7.2fs] iter %-3d %-24s H_T %zu/%zu  H_TE %zu/%zu  H_M %zu/%zu  H_ME %zu/%zu  constraints %zu\n",
               last_print_, iteration_, log::toString(phase_), counts_[0][0], counts_[0][1], counts_[1][0],
               counts_[1][1], counts_[2][0], counts_[2][1], counts_[3][0], counts_[3][1], constraints_);
  std::fflush(out_);
}

}  // namespace dash
