#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "io/vrml/lexer.h"

using namespace radbake;
using namespace radbake::vrml;

namespace {
std::vector<Token> lexAll(std::string_view text) {
    Lexer lexer(text, "t.wrl");
    std::vector<Token> tokens;
    for (;;) {
        Token t = lexer.next();
        tokens.push_back(t);
        if (t.kind == TokenKind::End) return tokens;
    }
}
}  // namespace

TEST_CASE("lexer: words, numbers, braces; commas and comments are whitespace") {
    auto t = lexAll("#VRML V2.0 utf8\nDEF Box_1 Transform{translation 1,-2.5e1 +.5 # c\n children[]}");
    REQUIRE(t.size() == 13);
    CHECK(t[0].kind == TokenKind::Word);
    CHECK(t[0].text == "DEF");
    CHECK(t[0].line == 2);
    CHECK(t[0].column == 1);
    CHECK(t[1].text == "Box_1");
    CHECK(t[2].text == "Transform");
    CHECK(t[3].kind == TokenKind::OpenBrace);
    CHECK(t[3].column == 20);
    CHECK(t[4].text == "translation");
    CHECK(t[5].kind == TokenKind::Number);
    CHECK(t[5].text == "1");
    CHECK(t[6].text == "-2.5e1");
    CHECK(t[7].text == "+.5");
    CHECK(t[8].text == "children");
    CHECK(t[8].line == 3);
    CHECK(t[8].column == 2);
    CHECK(t[9].kind == TokenKind::OpenBracket);
    CHECK(t[10].kind == TokenKind::CloseBracket);
    CHECK(t[11].kind == TokenKind::CloseBrace);
}

TEST_CASE("lexer: CR, LF and CRLF each end one line; junk bytes in comments are skipped") {
    auto t = lexAll("a\r\nb\rc\nd # \xff\xfe\x01 junk\r\n e");
    REQUIRE(t.size() == 6);
    CHECK(t[1].line == 2);
    CHECK(t[2].line == 3);
    CHECK(t[3].line == 4);
    CHECK(t[4].text == "e");
    CHECK(t[4].line == 5);
    CHECK(t[4].column == 2);
}

TEST_CASE("lexer: strings keep escapes until decoded and may span lines") {
    auto t = lexAll("\"a \\\"q\\\" \\\\ b\nc\" x \"open");
    REQUIRE(t.size() == 4);
    CHECK(t[0].kind == TokenKind::String);
    CHECK(Lexer::decodeString(t[0]) == "a \"q\" \\ b\nc");
    CHECK(t[1].text == "x");
    CHECK(t[1].line == 2);
    CHECK(t[2].kind == TokenKind::Invalid);  // unterminated
    CHECK(t[2].column == 6);
}

TEST_CASE("lexer: number conversions") {
    auto t = lexAll("0x1F -0xff 0xFFFFFFFF 12 -7 3.0 1e-50 2.5 .5e1 1.5f - 0x 2147483648 1e400 nan");
    int32_t i = 0;
    CHECK(Lexer::toInt32(t[0], i));
    CHECK(i == 31);
    CHECK(Lexer::toInt32(t[1], i));
    CHECK(i == -255);
    CHECK(Lexer::toInt32(t[2], i));
    CHECK(i == -1);  // full 32-bit pattern, as SFImage pixels use
    CHECK(Lexer::toInt32(t[3], i));
    CHECK(i == 12);
    CHECK(Lexer::toInt32(t[4], i));
    CHECK(i == -7);
    CHECK(Lexer::toInt32(t[5], i));  // integral float accepted
    CHECK(i == 3);
    CHECK_FALSE(Lexer::toInt32(t[7], i));
    float f = 1.0f;
    CHECK(Lexer::toFloat(t[6], f));
    CHECK(f == 0.0f);
    CHECK(Lexer::toFloat(t[7], f));
    CHECK(f == 2.5f);
    CHECK(Lexer::toFloat(t[8], f));
    CHECK(f == 5.0f);
    CHECK(t[9].text == "1.5f");
    CHECK_FALSE(Lexer::toFloat(t[9], f));
    CHECK_FALSE(Lexer::toFloat(t[10], f));
    CHECK_FALSE(Lexer::toInt32(t[11], i));
    CHECK_FALSE(Lexer::toInt32(t[12], i));  // out of int32 range
    double d = 0.0;
    CHECK(Lexer::toDouble(t[13], d));
    CHECK(std::isinf(d));
    CHECK(t[14].kind == TokenKind::Word);
    CHECK_FALSE(Lexer::toDouble(t[14], d));
}

TEST_CASE("lexer: squeezed numbers, peek, and bytes that start no token") {
    Lexer lexer("1-2 a.b 'x", "t.wrl");
    CHECK(lexer.peek().text == "1");
    CHECK(lexer.next().text == "1");
    CHECK(lexer.next().text == "-2");
    CHECK(lexer.next().text == "a.b");
    Token bad = lexer.next();
    CHECK(bad.kind == TokenKind::Invalid);
    CHECK(lexer.location(bad).column == 9);
    CHECK(lexer.location(bad).file == "t.wrl");
    CHECK(lexer.next().text == "x");
    CHECK(lexer.next().kind == TokenKind::End);
    CHECK(lexer.next().kind == TokenKind::End);
}
