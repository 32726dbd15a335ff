// A library opened on demand (core/shared_library.h), against the C
// library's own functions, and what it says where it cannot.
#include "core/shared_library.h"

#include <gtest/gtest.h>

#include <cstring>

namespace cgview {
namespace {

TEST(SharedLibrary, FindsAFunctionThatWorks) {
  SharedLibrary libc("libc.so.6");
  ASSERT_TRUE(libc.opened()) << libc.why();
  const auto length = libc.function<std::size_t (*)(const char*)>("strlen");
  ASSERT_NE(length, nullptr);
  EXPECT_EQ(length("seven c"), 7u);
  EXPECT_EQ(libc.why(), "");
}

TEST(SharedLibrary, SaysWhichFunctionIsMissing) {
  SharedLibrary libc("libc.so.6");
  EXPECT_EQ(libc.function<void (*)()>("cgview_no_such_function"), nullptr);
  EXPECT_NE(libc.why().find("cgview_no_such_function"), std::string::npos) << libc.why();
}

TEST(SharedLibrary, SaysWhyALibraryDidNotOpen) {
  SharedLibrary none("/nonexistent/libcgview_none.so");
  EXPECT_FALSE(none.opened());
  EXPECT_NE(none.why().find("/nonexistent/libcgview_none.so"), std::string::npos) << none.why();
  EXPECT_EQ(none.function<void (*)()>("anything"), nullptr);
}

}  // namespace
}  // namespace cgview
