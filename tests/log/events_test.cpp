#include <gtest/gtest.h>

#include "engine/events/event_batch.h"
#include "engine/events/event_emitter.h"
#include "engine/events/memory_sink.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

TEST(Events, MemorySinkCountsByLayerKindAndType) {
  MemorySink sink;
  EventEmitter em(&sink);
  em.vertex(Layer::Task, 0, "R1");
  em.vertex(Layer::Task, 1, "O1@start");
  em.hyperarc(Layer::Task, "pick", 0, {2}, {0, 1}, "R1 picks O1");
  em.hyperarc(Layer::Task, "handover", 1, {3}, {2}, "R1 -> R2");
  em.vertex(Layer::Motion, 0);
  em.vertex(Layer::Motion, 1);
  em.removed(Layer::Motion, ElementKind::Vertex, 1);
  em.constraint(ConstraintKind::History, ConstraintAction::Created, 0, "(v_pre=1, v_post=2)", {1, 2}, "collision");
  em.constraint(ConstraintKind::History, ConstraintAction::Lifted, 0, "", {1, 2});
  em.taskSpaceExpansion(1, "O1", "stable pose 3", "order would reverse");
  em.counter("collision_checks_eager", 5);
  em.counter("collision_checks_eager", 9);

  EXPECT_EQ(sink.count(Layer::Task, ElementKind::Vertex), 2);
  EXPECT_EQ(sink.count(Layer::Task, ElementKind::Hyperarc), 2);
  EXPECT_EQ(sink.countHyperarcs(Layer::Task, "handover"), 1);
  EXPECT_EQ(sink.count(Layer::Motion, ElementKind::Vertex), 1);  // added 2, removed 1
  EXPECT_EQ(sink.count(Layer::TaskExtended, ElementKind::Vertex), 0);
  EXPECT_EQ(sink.countConstraints(ConstraintKind::History, ConstraintAction::Created), 1);
  EXPECT_EQ(sink.countConstraints(ConstraintKind::History, ConstraintAction::Lifted), 1);
  EXPECT_EQ(sink.countTaskSpaceExpansions(), 1);
  EXPECT_EQ(sink.counter("collision_checks_eager"), 9);
  EXPECT_EQ(sink.counter("missing", -1), -1);
  EXPECT_EQ(sink.size(), 12u);
}

TEST(Events, TimestampsAreMonotonicAndCarryTheIteration) {
  MemorySink sink;
  EventEmitter em(&sink);
  for (int i = 0; i < 100; ++i) {
    em.setIteration(i / 10);
    em.vertex(Layer::Task, static_cast<std::uint32_t>(i));
  }
  const auto events = sink.events();
  for (std::size_t i = 1; i < events.size(); ++i) {
    EXPECT_GE(events[i].t, events[i - 1].t);
    EXPECT_EQ(events[i].iteration, static_cast<int>(i) / 10);
  }
}

TEST(Events, PhaseTimerEmitsStartAndEndAndAccumulates) {
  MemorySink sink;
  EventEmitter em(&sink);
  {
    PhaseTimer a(em, Phase::TaskQuery);
  }
  double second = 0.0;
  {
    PhaseTimer b(em, Phase::TaskQuery);
    second = b.stop();
    EXPECT_EQ(b.stop(), 0.0);  // stopping twice ends it once
  }
  const auto events = sink.events();
  ASSERT_EQ(events.size(), 4u);
  const auto& start = std::get<PhaseEvent>(events[0].payload);
  const auto& end = std::get<PhaseEvent>(events[1].payload);
  EXPECT_EQ(start.boundary, PhaseBoundary::Start);
  EXPECT_EQ(end.boundary, PhaseBoundary::End);
  EXPECT_DOUBLE_EQ(end.duration, events[1].t - events[0].t);
  EXPECT_DOUBLE_EQ(em.phaseTotals()[static_cast<int>(Phase::TaskQuery)], end.duration + second);
  EXPECT_DOUBLE_EQ(sink.phaseSeconds(Phase::TaskQuery), em.phaseTotals()[static_cast<int>(Phase::TaskQuery)]);
  EXPECT_EQ(em.phaseTotals()[static_cast<int>(Phase::MotionQuery)], 0.0);
}

TEST(Events, AnEmitterWithoutSinkStillTimesPhases) {
  EventEmitter em(nullptr);
  EXPECT_FALSE(em.enabled());
  em.vertex(Layer::Task, 0);
  { PhaseTimer t(em, Phase::Other); }
  EXPECT_GE(em.phaseTotals()[static_cast<int>(Phase::Other)], 0.0);
}

TEST(Events, TeeSinkForwardsToEverySink) {
  MemorySink a, b;
  NullSink none;
  TeeSink tee({&a, &none, &b});
  EventEmitter em(&tee);
  testing::emitScriptedRun(em, 10);
  EXPECT_GT(a.size(), 100u);
  EXPECT_EQ(a.size(), b.size());
}

std::vector<std::uint32_t> toVector(const IdView& ids) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = 0; i < ids.size(); ++i) out.push_back(ids[i]);
  return out;
}

// The recorder's flat batch gives back every field of every payload type, in order, including empty
// and long strings, empty and long id lists, and bytes that are not plain ASCII.
TEST(Events, ABatchGivesBackEveryFieldInOrder) {
  std::vector<std::uint32_t> many(1000);
  for (std::uint32_t i = 0; i < many.size(); ++i) many[i] = 4'000'000'000u - i;
  const std::string long_text(70'000, 'x');
  std::vector<Event> events;
  events.push_back({0.125, 3, RepresentationEvent{.layer = Layer::MotionExtended, .kind = ElementKind::Hyperarc,
                                                  .arc_type = "transition", .id = 7, .head = {1}, .tail = many,
                                                  .label = "R1 \xe2\x86\x92 R2 \"quoted\""}});
  events.push_back({0.25, 3, RepresentationEvent{.layer = Layer::Task, .change = ElementChange::Removed, .id = 9}});
  events.push_back({0.5, 4, ConstraintEvent{ConstraintKind::Interaction, ConstraintAction::Lifted, 11, long_text, {}, ""}});
  events.push_back({0.75, 5, TaskSpaceExpansionEvent{12, "O3", "pose 4", ""}});
  events.push_back({1.0, 5, PhaseEvent{Phase::ConflictResolution, PhaseBoundary::End, 0.5}});
  events.push_back({1.5, -1, CounterEvent{"collision_checks_lazy", -42}});
  events.push_back({2.0, 6, RepresentationEvent{.layer = Layer::TaskExtended, .id = 0xffffffffu, .label = ""}});

  EventBatch batch(16);  // far too small: it grows
  for (const Event& e : events) batch.append(e);
  EXPECT_EQ(batch.events(), events.size());
  EventBatch moved = std::move(batch);

  EventBatch::Reader reader(moved);
  EventView v;
  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.type, 0u);
  EXPECT_EQ(v.t, 0.125);
  EXPECT_EQ(v.iteration, 3);
  EXPECT_EQ(v.layer, Layer::MotionExtended);
  EXPECT_EQ(v.kind, ElementKind::Hyperarc);
  EXPECT_EQ(v.change, ElementChange::Added);
  EXPECT_EQ(v.arc_type, "transition");
  EXPECT_EQ(v.id, 7u);
  EXPECT_EQ(toVector(v.head), std::vector<std::uint32_t>{1});
  EXPECT_EQ(toVector(v.tail), many);
  EXPECT_EQ(v.label, "R1 \xe2\x86\x92 R2 \"quoted\"");

  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.type, 0u);
  EXPECT_EQ(v.layer, Layer::Task);
  EXPECT_EQ(v.kind, ElementKind::Vertex);
  EXPECT_EQ(v.change, ElementChange::Removed);
  EXPECT_TRUE(v.arc_type.empty() && v.label.empty() && v.head.empty() && v.tail.empty());

  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.type, 1u);
  EXPECT_EQ(v.constraint_kind, ConstraintKind::Interaction);
  EXPECT_EQ(v.action, ConstraintAction::Lifted);
  EXPECT_EQ(v.id, 11u);
  EXPECT_EQ(v.content, long_text);
  EXPECT_TRUE(v.vertices.empty());
  EXPECT_EQ(v.conflict, "");

  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.type, 2u);
  EXPECT_EQ(v.id, 12u);
  EXPECT_EQ(v.object_label, "O3");
  EXPECT_EQ(v.added, "pose 4");
  EXPECT_EQ(v.reason, "");

  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.type, 3u);
  EXPECT_EQ(v.phase, Phase::ConflictResolution);
  EXPECT_EQ(v.boundary, PhaseBoundary::End);
  EXPECT_EQ(v.duration, 0.5);

  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.type, 4u);
  EXPECT_EQ(v.t, 1.5);
  EXPECT_EQ(v.iteration, -1);
  EXPECT_EQ(v.name, "collision_checks_lazy");
  EXPECT_EQ(v.value, -42);

  ASSERT_TRUE(reader.next(v));
  EXPECT_EQ(v.layer, Layer::TaskExtended);
  EXPECT_EQ(v.id, 0xffffffffu);
  EXPECT_FALSE(reader.next(v));
  EXPECT_FALSE(EventBatch::Reader(EventBatch()).next(v));
}

TEST(Events, NamesMatchTheDatabaseVocabulary) {
  EXPECT_STREQ(toString(Layer::TaskExtended), "task_extended");
  EXPECT_STREQ(toString(Layer::MotionExtended), "motion_extended");
  EXPECT_STREQ(toString(Phase::TaskConflictDetection), "task_conflict_detection");
  EXPECT_STREQ(toString(ConstraintKind::Interaction), "interaction");
  EXPECT_STREQ(typeName(EventPayload{CounterEvent{}}), "counter");
  EXPECT_STREQ(typeName(EventPayload{TaskSpaceExpansionEvent{}}), "task_space_expansion");
}

}  // namespace
}  // namespace dash::log
