#pragma once
// One roadmap per planning space: a robot with an empty hand, or holding an object (the paper's
// "roadmaps per planning space"). Both planners keep theirs in this container.
#include <cstddef>
#include <memory>
#include <vector>

namespace dash {

template <class Roadmap>
class PerPlanningSpace {
 public:
  PerPlanningSpace() = default;
  explicit PerPlanningSpace(int robots) : slots_(static_cast<std::size_t>(robots) * 2) {}

  /// The slot of (robot, hand state); empty until a roadmap is put there.
  std::unique_ptr<Roadmap>& slot(int robot, bool holding) { return slots_[index(robot, holding)]; }
  const std::unique_ptr<Roadmap>& slot(int robot, bool holding) const { return slots_[index(robot, holding)]; }
  /// The roadmap of (robot, hand state), which must exist.
  Roadmap& at(int robot, bool holding) { return *slot(robot, holding); }

  /// Every slot, robot by robot, empty hand first.
  auto begin() { return slots_.begin(); }
  auto end() { return slots_.end(); }
  auto begin() const { return slots_.begin(); }
  auto end() const { return slots_.end(); }

 private:
  static std::size_t index(int robot, bool holding) { return static_cast<std::size_t>(robot) * 2 + (holding ? 1 : 0); }
  std::vector<std::unique_ptr<Roadmap>> slots_;
};

}  // namespace dash
