// read_progress_lines: a worker's progress pipe parsed line by line, and
// anything else on it (the sign of a broken worker) said, quoting it.
#include <gtest/gtest.h>

#include <string>

#include "jobs/executor.h"

namespace cgview::server {
namespace {

const std::string kGarbage = "the worker wrote something other than progress on its progress pipe: ";

TEST(ProgressLines, TheLastWholeLineCountsAndAPartialOneWaits) {
  std::string out = "progress 0.25 reading\nprogress 0.5000 rays\nprogress 0.7";
  double f = -1;
  std::string stage;
  const ProgressRead r = read_progress_lines(out, f, stage);
  EXPECT_TRUE(r.found);
  EXPECT_EQ(r.garbage, "");
  EXPECT_DOUBLE_EQ(f, 0.5);
  EXPECT_EQ(stage, "rays");
  EXPECT_EQ(out, "progress 0.7");  // kept for the next read
  out += "5\n";
  EXPECT_TRUE(read_progress_lines(out, f, stage).found);
  EXPECT_DOUBLE_EQ(f, 0.75);
  EXPECT_EQ(stage, "");
  EXPECT_EQ(out, "");
}

TEST(ProgressLines, FractionsOutsideZeroToOneAreClamped) {
  std::string out = "progress 7 past the end\n";
  double f = 0;
  std::string stage;
  EXPECT_TRUE(read_progress_lines(out, f, stage).found);
  EXPECT_DOUBLE_EQ(f, 1.0);
  EXPECT_EQ(stage, "past the end");
}

TEST(ProgressLines, AnythingElseIsGarbageQuotedAndStopsTheReading) {
  const struct {
    std::string out, said;
  } cases[] = {
      {"hello\nprogress 0.5 x\n", "\"hello\""},
      {"progress 0.1 a\nprogress banana\n", "\"progress banana\""},
      {"progress nan stage\n", "\"progress nan stage\""},
      {"progress inf\n", "\"progress inf\""},
      {"progress 0.5x\n", "\"progress 0.5x\""},
      {"\n", "\"\""},
      {std::string("bin\x01\xff") + "ary\n", "\"bin??ary\""},
      {std::string(100, 'z') + "\n", "\"" + std::string(60, 'z') + "...\""},
      {"progress 0.5 " + std::string(5000, 's') + "\n", "a line of 5013 bytes"},
      {std::string(5000, 'x'), "5000 bytes without a line end"},
  };
  for (const auto& c : cases) {
    std::string out = c.out;
    double f = -1;
    std::string stage;
    const ProgressRead r = read_progress_lines(out, f, stage);
    EXPECT_EQ(r.garbage, kGarbage + c.said) << c.out.substr(0, 40);
    EXPECT_EQ(out, "") << "nothing is kept after garbage";
  }
}

TEST(ProgressLines, AFullLineUpToTheLimitIsNotGarbage) {
  std::string out(kMaxProgressLine, 'p');  // no line end yet, but not over the limit
  double f = 0;
  std::string stage;
  EXPECT_EQ(read_progress_lines(out, f, stage).garbage, "");
  EXPECT_EQ(out.size(), kMaxProgressLine);
}

}  // namespace
}  // namespace cgview::server
