#include <gtest/gtest.h>

#include "engine/core/check.h"
#include "server/cli/args.h"

namespace dash::cli {
namespace {

TEST(Args, OptionsFlagsPositionalsAndKeyValues) {
  Args a({"sorting", "--seed", "3", "--out=x.json", "--json", "robots=4"},
         {.options = {"seed", "out"}, .flags = {"json"}, .key_values = true});
  EXPECT_EQ(a.integer("seed", 0), 3);
  EXPECT_EQ(a.get("out", ""), "x.json");
  EXPECT_TRUE(a.has("json"));
  ASSERT_EQ(a.positional().size(), 1u);
  EXPECT_EQ(a.positional()[0], "sorting");
  ASSERT_EQ(a.keyValues().size(), 1u);
  EXPECT_EQ(a.keyValues()[0].first, "robots");
}

TEST(Args, UnknownOptionAndBadNumbersAreInputErrors) {
  EXPECT_THROW(Args({"--nope"}, {}), InputError);
  EXPECT_THROW(Args({"--seed"}, {.options = {"seed"}}), InputError);
  Args a({"--seed", "x1"}, {.options = {"seed"}});
  EXPECT_THROW(a.integer("seed", 0), InputError);
  EXPECT_THROW(parseNumberList("1,nan,3", "--q"), InputError);
  EXPECT_EQ(parseNumberList("1,2.5,-3", "--q").size(), 3u);
  EXPECT_THROW(parseNumberList("1,,3", "--q"), InputError);
  EXPECT_THROW(parseNumberList("1,2,", "--q"), InputError);
}

}  // namespace
}  // namespace dash::cli
