#pragma once
// Internal to Scheduler::build: the schedule being built (ScheduleBuild) and the placing of one task
// step in it (StepScheduler). Not for other callers.
//
// A step is placed at the earliest transition time T its dependencies and its robots allow. At each T
// every arrival mode is tried in turn; a conflict is repaired (the repair ladder below) and the same
// mode tried again, else the next mode; when no mode is free of conflicts T moves on by delay_step
// (retiming), up to max_delay after the last busy robot in the way has finished its schedule.
//
// Repair ladder, first that applies:
//   1. the partner of a handover in the way: replan the transits of this arrival mode around it;
//   2. a robot standing still in the way (its schedule has ended): replan the transits around it;
//   3. that did not help: send the idle robot home (idle_arms_home);
//   4. the composite path itself in conflict among its movers: plan it again;
//   5. still in conflict with the partner or a standing robot: plan the robots involved together in
//      their composite space (ARC's subproblem), adding the robot in the way to it.
#include <optional>
#include <string>
#include <vector>

#include "engine/conflict/scheduler.h"

namespace dash {

/// How the participants of a step reach their transition configurations.
enum class ArrivalMode {
  kTogether = 0,       ///< each on its own path, arriving together
  kGiverFirst = 1,     ///< handovers: the giver in place before the receiver leaves
  kReceiverFirst = 2,  ///< handovers: the receiver waits at its approach start while the giver comes
  kComposite = 3,      ///< the composite path of ARC's subproblem (once there is one)
};
inline constexpr int kArrivalModeCount = 4;
const char* toString(ArrivalMode mode);

/// The schedule being built: its state and what every step needs.
struct ScheduleBuild {
  const Scheduler& scheduler;
  ScheduleChecker& checker;
  const SchedulerParams& params;
  const Scene& scene;
  ScheduleState& state;
  MotionLayerResult& motion;
  std::vector<std::size_t> next_visit;  ///< per robot: its next visit in `motion`
  const MoveReplanner& replan;
  const Deadline& deadline;
  ScheduleStats& stats;
  const TaskPlan& plan;
  const lazy::MotionConstraintSet* constraints;  ///< regions a replanned move into a step keeps out of (or null)
  const std::vector<StepWindow>* windows;        ///< clock-time windows the robots' steps keep out of (or null)

  /// The regions robot's move into `step` (at transition configuration q) keeps out of
  /// (MotionConstraintSet::regionsFor).
  std::vector<Aabb> regionsFor(int robot, int step, const JointVector& q) const;

  /// The earliest start >= from of a piece of `duration` seconds of robot's part in `step` clear of the
  /// windows (from itself when there are none; see clearOfWindows).
  double clearFrom(int robot, int step, double from, double duration) const {
    return windows ? clearOfWindows(*windows, robot, step, from, duration) : from;
  }

  /// The other robots standing still from time t on (their schedules end before t), for replanning.
  std::vector<RobotState> parkedAt(int self, double t) const;
  /// The next visit's transit must start where the robot now stands (after a skipped retreat or an
  /// eviction): replan it from there. False when there is no way.
  bool fixNextTransit(int robot);
  /// Moves an idle robot from where it stands to its home configuration, as soon as that is clear.
  bool sendHome(int robot);
};

class StepScheduler {
 public:
  StepScheduler(ScheduleBuild& build, const TaskPlan& plan, int step, const TransitionConfig& tc,
                const TaskSpace& space);

  /// Places the step (its robots' transits, approaches and the transition) in the schedule: nullopt
  /// when placed, else why not.
  std::optional<std::string> place();
  /// After place() failed: the conflict that retiming and the repairs met last (if any).
  const std::optional<ScheduleConflict>& lastConflict() const { return last_conflict_; }
  /// The timelines of lastConflict()'s robot and other robot in the trial that met it (null: none).
  const RobotTimeline* lastConflictRobot() const { return last_robot_ ? &*last_robot_ : nullptr; }
  const RobotTimeline* lastConflictOther() const { return last_other_ ? &*last_other_ : nullptr; }
  /// After place(): the plan events of the transition, and the retreats. False (with `why`) when a
  /// robot has no way on from where it stays.
  bool finish(std::string& why);

 private:
  struct Participant {
    int robot = -1;
    const StepVisit* visit = nullptr;
    std::vector<JointVector> transit;
    double transit_time = 0.0;
    double approach_time = 0.0;
    std::vector<double> approach_times;  ///< of visit->approach's waypoints, from 0 to approach_time
    /// Staggered arrival modes (kGiverFirst, kReceiverFirst): transits replanned around the partner.
    std::vector<JointVector> staggered[3];
    double staggered_time[3] = {0.0, 0.0, 0.0};
    bool staggered_tried[3] = {false, false, false};
  };
  enum class Repair { kSameModeAgain, kComposite, kNone };

  /// Appends p's approach to c so that it arrives at its transition configuration at T.
  void appendApproach(RobotTimeline& c, const Participant& p, double T) const;
  int modes() const;  ///< individual arrival modes for this step (1, or 3 for a handover)
  double earliest() const;
  /// Participants' arrival times at their approach starts for an individual mode at T.
  std::vector<double> arrivals(ArrivalMode mode, double T) const;
  double travel(int i, ArrivalMode mode) const;
  /// How much later than T the step must happen for every participant, arriving together, to keep its
  /// piece of the step out of its clock-time windows (0: it fits at T; StepWindow).
  double windowWait(double T) const;
  /// The timelines with this step placed at T in `mode`; nullopt when the mode does not fit at T.
  std::optional<std::vector<RobotTimeline>> trial(ArrivalMode mode, double T) const;
  std::optional<ScheduleConflict> check(const std::vector<RobotTimeline>& trial, ArrivalMode mode, double T) const;
  Repair repair(const ScheduleConflict& conflict, ArrivalMode mode);
  bool replanComposite();
  void replanTransits(ArrivalMode mode);
  /// Takes the trial; false (with `why`) when a robot that stepped aside has no way on.
  bool commit(std::vector<RobotTimeline> trial, ArrivalMode mode, double T, std::string& why);
  std::string lastConflictText() const;

  ScheduleBuild& b_;
  const TaskPlan& plan_;
  const TaskSpace& space_;
  const int k_;
  const TaskArc& a_;
  const TransitionConfig& tc_;
  std::vector<Participant> parts_;
  double T_ = 0.0;  ///< the transition time, once placed
  std::optional<ScheduleConflict> last_conflict_;
  std::optional<RobotTimeline> last_robot_;  ///< the robot of last_conflict_, as its trial had it
  std::optional<RobotTimeline> last_other_;  ///< the other robot of last_conflict_, as its trial had it
  std::vector<int> blockers_;  ///< robots found standing in the way of this step
  std::vector<int> evicted_;   ///< idle robots sent home to clear the way for this step
  /// ARC's subproblem for this step: the participants first, then robots standing in their way.
  std::vector<int> movers_;
  std::optional<CompositePath> composite_;
  std::vector<double> composite_steps_;
  double composite_time_ = 0.0;
  int composite_tries_ = 0;
  double max_approach_ = 0.0;
};

}  // namespace dash
