// printable(): quoted input made safe for a terminal, other scripts kept readable.
#include <gtest/gtest.h>

#include <string>

#include "rayscout/core/input_error.h"

namespace rayscout {
namespace {

TEST(Printable, KeepsAsciiAndEscapesControlBytes) {
  EXPECT_EQ(printable("plain name.obj"), "plain name.obj");
  EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable("\x1b[2J\x07\x7f"), "\\x1b[2J\\x07\\x7f");
}

TEST(Printable, KeepsWellFormedUtf8) {
  EXPECT_EQ(printable("caf\xc3\xa9"), "caf\xc3\xa9");                   // é
  EXPECT_EQ(printable("\xe5\x9c\xb0\xe5\x9b\xbe"), "\xe5\x9c\xb0\xe5\x9b\xbe");  // 地图
  EXPECT_EQ(printable("\xf0\x9f\x99\x82"), "\xf0\x9f\x99\x82");           // U+1F642
}

TEST(Printable, EscapesBytesThatAreNotUtf8) {
  // A binary magic (PNG) and a Latin-1 name: raw, they print as garbage or worse.
  EXPECT_EQ(printable("\x89PNG"), "\\x89PNG");
  EXPECT_EQ(printable("caf\xe9.obj"), "caf\\xe9.obj");
  EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(printable("\xc3"), "\\xc3");                      // truncated sequence
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");             // overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");    // surrogate U+D800
  EXPECT_EQ(printable("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
}

TEST(Printable, EscapesC1Controls) {
  // U+009B is CSI: a terminal reads "<CSI>2J" as "clear the screen", as it does ESC [ 2 J.
  EXPECT_EQ(printable("\x9b" "2J"), "\\x9b2J");
  EXPECT_EQ(printable("\xc2\x9b" "2J"), "\\xc2\\x9b2J");
  EXPECT_EQ(printable("\xc2\xa0"), "\xc2\xa0");  // U+00A0, the first printable one
}

}  // namespace
}  // namespace rayscout
