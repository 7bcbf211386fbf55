#include "engine/hypergraph/hypergraph.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dash {
namespace {

using Graph = Hypergraph<std::string, std::string>;

TEST(Hypergraph, AddingAnEqualVertexReturnsTheExistingId) {
  Graph g;
  const auto r1 = g.addVertex("R1");
  const auto r2 = g.addVertex("R2");
  const auto again = g.addVertex("R1");
  EXPECT_TRUE(r1.inserted);
  EXPECT_TRUE(r2.inserted);
  EXPECT_FALSE(again.inserted);
  EXPECT_EQ(again.id, r1.id);
  EXPECT_NE(r1.id, r2.id);
  EXPECT_EQ(g.vertexCount(), 2u);
  EXPECT_EQ(g.find("R2"), r2.id);
  EXPECT_FALSE(g.find("R3").has_value());
  EXPECT_EQ(g.property(r1.id), "R1");
}

TEST(Hypergraph, HyperarcSetsAreOrderIndependent) {
  Graph g;
  const VertexId r = g.addVertex("R1").id, o = g.addVertex("O_s").id, ro = g.addVertex("R1+O").id;
  const auto pick = g.addHyperarc({r, o}, {ro}, "pick");
  const auto same = g.addHyperarc({o, r, o}, {ro, ro}, "pick");
  EXPECT_TRUE(pick.inserted);
  EXPECT_FALSE(same.inserted);
  EXPECT_EQ(same.id, pick.id);
  EXPECT_EQ(g.hyperarcCount(), 1u);
  // The same sets with another property, or the sets swapped, are other hyperarcs.
  EXPECT_TRUE(g.addHyperarc({r, o}, {ro}, "pick-top").inserted);
  EXPECT_TRUE(g.addHyperarc({ro}, {r, o}, "pick").inserted);
  EXPECT_EQ(g.hyperarcCount(), 3u);
  // Stored canonically: sorted, without repeats.
  ASSERT_EQ(g.tail(pick.id).size(), 2u);
  EXPECT_LT(g.tail(pick.id)[0], g.tail(pick.id)[1]);
  EXPECT_EQ(g.find({o, r}, {ro}, "pick"), pick.id);
  EXPECT_FALSE(g.find({o, r}, {ro}, "place").has_value());
}

TEST(Hypergraph, IncomingAndOutgoingLists) {
  Graph g;
  const VertexId r1 = g.addVertex("R1").id, r2 = g.addVertex("R2").id, o = g.addVertex("O_s").id;
  const VertexId r1o = g.addVertex("R1+O").id, r2o = g.addVertex("R2+O").id;
  const HyperarcId pick = g.addHyperarc({r1, o}, {r1o}, "pick").id;
  const HyperarcId handover = g.addHyperarc({r1o, r2}, {r1, r2o}, "handover").id;
  auto list = [](std::span<const HyperarcId> s) { return std::vector<HyperarcId>(s.begin(), s.end()); };
  EXPECT_EQ(list(g.outgoing(r1)), std::vector{pick});
  EXPECT_EQ(list(g.incoming(r1)), std::vector{handover});
  EXPECT_EQ(list(g.outgoing(o)), std::vector{pick});
  EXPECT_TRUE(g.incoming(o).empty());
  EXPECT_EQ(list(g.outgoing(r1o)), std::vector{handover});
  EXPECT_EQ(list(g.incoming(r1o)), std::vector{pick});
  EXPECT_EQ(list(g.outgoing(r2)), std::vector{handover});
  EXPECT_TRUE(g.incoming(r2).empty());
  EXPECT_EQ(list(g.incoming(r2o)), std::vector{handover});
  EXPECT_TRUE(g.outgoing(r2o).empty());
  // Re-adding an existing hyperarc does not grow the lists.
  g.addHyperarc({r2, r1o}, {r2o, r1}, "handover");
  EXPECT_EQ(g.outgoing(r2).size(), 1u);
}

TEST(Hypergraph, IterationAndClear) {
  Graph g;
  for (const char* name : {"a", "b", "c"}) g.addVertex(name);
  g.addHyperarc({VertexId(0)}, {VertexId(1)}, "x");
  std::vector<std::string> names;
  for (VertexId v : g.vertices()) names.push_back(g.property(v));
  EXPECT_EQ(names, (std::vector<std::string>{"a", "b", "c"}));
  std::size_t arcs = 0;
  for (HyperarcId a : g.hyperarcs()) arcs += g.contains(a) ? 1 : 0;
  EXPECT_EQ(arcs, 1u);
  g.clear();
  EXPECT_EQ(g.vertexCount(), 0u);
  EXPECT_EQ(g.hyperarcCount(), 0u);
  EXPECT_FALSE(g.find("a").has_value());
  EXPECT_TRUE(g.addVertex("a").inserted);
}

TEST(Hypergraph, UnknownVertexInAHyperarcThrows) {
  Graph g;
  const VertexId a = g.addVertex("a").id;
  EXPECT_THROW(g.addHyperarc({a}, {VertexId(7)}, "x"), InputError);
  EXPECT_THROW(g.addHyperarc({VertexId()}, {a}, "x"), InputError);
}

// Every property hashes alike: the lookup must still tell them apart by equality.
struct Clash {
  int value;
  bool operator==(const Clash&) const = default;
};

}  // namespace
}  // namespace dash

template <>
struct std::hash<dash::Clash> {
  std::size_t operator()(const dash::Clash&) const noexcept { return 42; }
};

namespace dash {
namespace {

TEST(Hypergraph, EqualHashesAreToldApartByEquality) {
  Hypergraph<Clash, Clash> g;
  const VertexId a = g.addVertex({1}).id, b = g.addVertex({2}).id;
  EXPECT_NE(a, b);
  EXPECT_EQ(g.addVertex({2}).id, b);
  const HyperarcId x = g.addHyperarc({a}, {b}, {1}).id;
  const HyperarcId y = g.addHyperarc({a}, {b}, {2}).id;
  EXPECT_NE(x, y);
  EXPECT_EQ(g.addHyperarc({a}, {b}, {2}).id, y);
}

}  // namespace
}  // namespace dash
