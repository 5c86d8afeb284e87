#include "common/error.h"

#include <gtest/gtest.h>

namespace mopad {
namespace {

TEST(InputError, FormatsWhereWhatGotExpected) {
  EXPECT_STREQ(InputError("a.yaml:3", "bad width", "-1", "> 0").what(),
               "a.yaml:3: error: bad width; got -1, expected > 0");
  EXPECT_STREQ(InputError("a.glb", "no scene").what(), "a.glb: error: no scene");
  EXPECT_STREQ(InputError("", "x", "", "y").what(), "error: x; expected y");
}

TEST(InputError, IsAlwaysOneLine) {
  const std::string m = InputError("f", "line one\nline two", "a\r\nb").what();
  EXPECT_EQ(m.find('\n'), std::string::npos);
  EXPECT_EQ(m.find('\r'), std::string::npos);
}

}  // namespace
}  // namespace mopad
