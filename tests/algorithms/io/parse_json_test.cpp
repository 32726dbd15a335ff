// JSON from outside with its nesting bounded (io/parse_json.h).
#include "io/parse_json.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "core/errors.h"

namespace cgview {
namespace {

TEST(ParseJson, DepthCountsArraysAndObjectsButNotBracketsInStrings) {
  EXPECT_EQ(json_depth("1"), 0);
  EXPECT_EQ(json_depth("[]"), 1);
  EXPECT_EQ(json_depth(R"({"a":[{"b":[1,2]}],"c":{}})"), 4);
  EXPECT_EQ(json_depth(R"(["[[[[", "\"[[[", {"k]]]":"{{"}])"), 2);
  EXPECT_EQ(json_depth("]]]][["), 2);  // not JSON: counted all the same, never negative
}

TEST(ParseJson, TooDeepIsInvalidInputSayingHowDeep) {
  const std::string deep = std::string(65, '[') + std::string(65, ']');
  try {
    (void)parse_json(deep, "the body");
    FAIL() << "65 levels were parsed";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "the body nests arrays and objects 65 deep; at most 64 are read");
  }
  EXPECT_TRUE(parse_json_or_discarded(deep).is_discarded());
  const std::string ok = std::string(64, '[') + std::string(64, ']');
  EXPECT_TRUE(parse_json(ok, "x").is_array());
  EXPECT_TRUE(parse_json_or_discarded(ok).is_array());
}

// nlohmann throws out_of_range, not parse_error, for "6e8618"; callers that
// catch parse_error let it through (fuzz_skeleton found it in the skeleton reader).
TEST(ParseJson, ANumberPastADoubleIsInvalidInputOrDiscarded) {
  try {
    (void)parse_json("[1, 36200e8618]", "the body");
    FAIL() << "parsed";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "the body holds a number too large for a double");
  }
  EXPECT_TRUE(parse_json_or_discarded("[1, 36200e8618]").is_discarded());
}

TEST(ParseJson, MalformedIsAParseErrorOrDiscarded) {
  EXPECT_THROW((void)parse_json("{\"a\":", "x"), nlohmann::json::parse_error);
  EXPECT_TRUE(parse_json_or_discarded("{\"a\":").is_discarded());
  EXPECT_EQ(parse_json(R"({"a":[1,2]})", "x")["a"][1], 2);
}

// What the limit is for: a value nested 100,000 deep parses (nlohmann's
// parser keeps its own stack) but printing it recursed once a level.
TEST(ParseJson, AHundredThousandLevelsAreRefusedBeforeAnythingRecurses) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_THROW((void)parse_json(deep, "x"), InvalidInput);
  EXPECT_TRUE(parse_json_or_discarded(deep).is_discarded());
}

}  // namespace
}  // namespace cgview
