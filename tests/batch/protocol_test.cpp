// The runner <-> run-one pipe protocol: every event payload and the result survive the trip, and
// a stream split at any byte decodes to the same frames.
#include <gtest/gtest.h>

#include "server/batch/run_protocol.h"

namespace dash::batch::proto {
namespace {

std::vector<log::Event> sampleEvents() {
  std::vector<log::Event> events;
  events.push_back({0.5, 1,
                    log::RepresentationEvent{.layer = log::Layer::MotionExtended,
                                             .kind = log::ElementKind::Hyperarc,
                                             .change = log::ElementChange::Removed,
                                             .arc_type = "handover",
                                             .id = 42,
                                             .head = {1, 2, 3},
                                             .tail = {7},
                                             .label = "R1+O3"}});
  events.push_back({0.75, 2,
                    log::ConstraintEvent{log::ConstraintKind::Interaction,
                                         log::ConstraintAction::Lifted,
                                         9,
                                         "(v_pre=12, v_post=40)",
                                         {12, 40},
                                         "swept volumes overlap"}});
  events.push_back({1.0, 2, log::TaskSpaceExpansionEvent{3, "obj_3", "pose 4", "history constraints"}});
  events.push_back({1.25, 3, log::PhaseEvent{log::Phase::ConflictResolution, log::PhaseBoundary::End, 0.125}});
  events.push_back({1.5, 3, log::CounterEvent{"collision_checks_lazy", 123456789012LL}});
  events.push_back({1.75, 3, log::ProgressEvent{log::Phase::ConflictResolution, 37, 146, 4.25, "ur5e_3, ur5e_7"}});
  events.push_back({2.0, 4, log::RepresentationEvent{}});  // empty strings and lists
  return events;
}

TEST(RunProtocol, EveryEventPayloadRoundTrips) {
  std::string stream;
  for (const auto& e : sampleEvents()) appendEvent(stream, e);
  FrameDecoder decoder;
  decoder.feed(stream.data(), stream.size());
  Frame frame;
  for (const auto& expected : sampleEvents()) {
    ASSERT_TRUE(decoder.next(frame));
    ASSERT_EQ(frame.type, MessageType::kEvent);
    const log::Event got = decodeEvent(frame.payload);
    EXPECT_DOUBLE_EQ(got.t, expected.t);
    EXPECT_EQ(got.iteration, expected.iteration);
    ASSERT_EQ(got.payload.index(), expected.payload.index());
    if (const auto* r = std::get_if<log::RepresentationEvent>(&expected.payload)) {
      const auto& g = std::get<log::RepresentationEvent>(got.payload);
      EXPECT_EQ(g.layer, r->layer);
      EXPECT_EQ(g.kind, r->kind);
      EXPECT_EQ(g.change, r->change);
      EXPECT_EQ(g.arc_type, r->arc_type);
      EXPECT_EQ(g.id, r->id);
      EXPECT_EQ(g.head, r->head);
      EXPECT_EQ(g.tail, r->tail);
      EXPECT_EQ(g.label, r->label);
    } else if (const auto* c = std::get_if<log::ConstraintEvent>(&expected.payload)) {
      const auto& g = std::get<log::ConstraintEvent>(got.payload);
      EXPECT_EQ(g.kind, c->kind);
      EXPECT_EQ(g.action, c->action);
      EXPECT_EQ(g.id, c->id);
      EXPECT_EQ(g.content, c->content);
      EXPECT_EQ(g.vertices, c->vertices);
      EXPECT_EQ(g.conflict, c->conflict);
    } else if (const auto* x = std::get_if<log::TaskSpaceExpansionEvent>(&expected.payload)) {
      const auto& g = std::get<log::TaskSpaceExpansionEvent>(got.payload);
      EXPECT_EQ(g.object_id, x->object_id);
      EXPECT_EQ(g.object_label, x->object_label);
      EXPECT_EQ(g.added, x->added);
      EXPECT_EQ(g.reason, x->reason);
    } else if (const auto* p = std::get_if<log::PhaseEvent>(&expected.payload)) {
      const auto& g = std::get<log::PhaseEvent>(got.payload);
      EXPECT_EQ(g.phase, p->phase);
      EXPECT_EQ(g.boundary, p->boundary);
      EXPECT_DOUBLE_EQ(g.duration, p->duration);
    } else if (const auto* w = std::get_if<log::ProgressEvent>(&expected.payload)) {
      const auto& g = std::get<log::ProgressEvent>(got.payload);
      EXPECT_EQ(g.phase, w->phase);
      EXPECT_EQ(g.done, w->done);
      EXPECT_EQ(g.total, w->total);
      EXPECT_DOUBLE_EQ(g.rate, w->rate);
      EXPECT_EQ(g.current, w->current);
    } else {
      const auto& k = std::get<log::CounterEvent>(expected.payload);
      const auto& g = std::get<log::CounterEvent>(got.payload);
      EXPECT_EQ(g.name, k.name);
      EXPECT_EQ(g.value, k.value);
    }
  }
  EXPECT_FALSE(decoder.next(frame));
  EXPECT_EQ(decoder.pending(), 0u);
}

TEST(RunProtocol, ResultHelloStartedAndErrorRoundTrip) {
  ChildResult r;
  r.outcome = PlanOutcome::kTimeout;
  r.message = "task layer: timeout";
  r.plan_json = "{\"format\":\"dashbench.plan/1\"}";
  r.task_plan_json = "[1,2]";
  r.stats.phase_seconds = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
  r.stats.sizes.task_vertices = 11;
  r.stats.sizes.motion_extended_hyperarcs = 88;
  r.stats.iterations = 5;
  r.stats.collision_checks_eager = 1000;
  r.stats.collision_checks_lazy = 2000;
  r.stats.task_space_expansions = 3;
  r.stats.makespan = 12.5;
  r.solve_seconds = 1.75;
  r.peak_memory_mb = 321.5;
  std::string stream;
  appendHello(stream, 4242);
  appendStarted(stream, "sorting-r4-o8-s1");
  appendResult(stream, r);
  appendError(stream, {"out-of-memory", "std::bad_alloc"});

  // Fed one byte at a time: frames only appear once whole.
  FrameDecoder decoder;
  std::vector<Frame> frames;
  for (char c : stream) {
    decoder.feed(&c, 1);
    Frame f;
    while (decoder.next(f)) frames.push_back(f);
  }
  ASSERT_EQ(frames.size(), 4u);
  const Hello hello = decodeHello(frames[0].payload);
  EXPECT_EQ(hello.version, kProtocolVersion);
  EXPECT_EQ(hello.pid, 4242);
  EXPECT_EQ(decodeStarted(frames[1].payload), "sorting-r4-o8-s1");
  const ChildResult got = decodeResult(frames[2].payload);
  EXPECT_EQ(got.outcome, PlanOutcome::kTimeout);
  EXPECT_EQ(got.message, r.message);
  EXPECT_EQ(got.plan_json, r.plan_json);
  EXPECT_EQ(got.task_plan_json, r.task_plan_json);
  EXPECT_EQ(got.stats.phase_seconds, r.stats.phase_seconds);
  EXPECT_EQ(got.stats.sizes.task_vertices, 11u);
  EXPECT_EQ(got.stats.sizes.motion_extended_hyperarcs, 88u);
  EXPECT_EQ(got.stats.iterations, 5);
  EXPECT_EQ(got.stats.collision_checks_eager, 1000);
  EXPECT_EQ(got.stats.collision_checks_lazy, 2000);
  EXPECT_EQ(got.stats.task_space_expansions, 3);
  EXPECT_DOUBLE_EQ(got.stats.makespan, 12.5);
  EXPECT_DOUBLE_EQ(got.solve_seconds, 1.75);
  EXPECT_DOUBLE_EQ(got.peak_memory_mb, 321.5);
  const ChildError error = decodeError(frames[3].payload);
  EXPECT_EQ(error.kind, "out-of-memory");
  EXPECT_EQ(error.message, "std::bad_alloc");
}

TEST(RunProtocol, MalformedInputIsAProtocolError) {
  FrameDecoder decoder;
  const std::string junk("Z\x01\x00\x00\x00x", 6);
  decoder.feed(junk.data(), junk.size());
  Frame f;
  EXPECT_THROW(decoder.next(f), ProtocolError);

  FrameDecoder huge;
  const std::string big = std::string("E") + "\xff\xff\xff\xff";
  huge.feed(big.data(), big.size());
  EXPECT_THROW(huge.next(f), ProtocolError);

  std::string stream;
  appendEvent(stream, sampleEvents()[0]);
  const std::string payload = stream.substr(5, stream.size() - 6);  // one byte short
  EXPECT_THROW(decodeEvent(payload), ProtocolError);
  EXPECT_THROW(decodeResult("abc"), ProtocolError);
  EXPECT_THROW(decodeHello(std::string(20, '\0')), ProtocolError);  // trailing bytes
}

}  // namespace
}  // namespace dash::batch::proto
