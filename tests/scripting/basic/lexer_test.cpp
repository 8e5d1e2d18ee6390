// The lexical rules of faulhaber.md §9.2: line ends, comments, keywords, numbers, object
// references, labels, operators and the errors of malformed tokens.
#include "scripting/basic/lexer.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mcemu::basic {
namespace {

std::vector<Tok> kinds(std::string_view line) {
  std::vector<Tok> out;
  for (const auto& t : lex_line(line).tokens) out.push_back(t.kind);
  return out;
}

TEST(BasicLexer, LinesEndWithCrLfOrCrLf) {
  EXPECT_EQ(split_lines("a\nb\r\nc\rd"), (std::vector<std::string_view>{"a", "b", "c", "d"}));
  EXPECT_EQ(split_lines("a\n\nb\n"), (std::vector<std::string_view>{"a", "", "b"}));
  EXPECT_EQ(split_lines("\r\n\r\n"), (std::vector<std::string_view>{"", ""}));
  EXPECT_EQ(split_lines("\n\r"), (std::vector<std::string_view>{"", ""}));  // LF, then CR: two ends
  EXPECT_TRUE(split_lines("").empty());
}

TEST(BasicLexer, CommentsRunToTheEndOfTheLine) {
  EXPECT_TRUE(lex_line("'a = 1").tokens.empty());
  EXPECT_TRUE(lex_line("   ' only a comment = $ # ü").tokens.empty());
  EXPECT_EQ(kinds("a = 1 ' set a"), (std::vector<Tok>{Tok::word, Tok::eq, Tok::number}));
}

TEST(BasicLexer, KeywordsAreCaseInsensitive) {
  for (const char* w : {"RETURN", "Return", "return", "rEtUrN"}) EXPECT_EQ(keyword(w), Kw::return_) << w;
  EXPECT_EQ(keyword("ENDIF"), Kw::endif);
  EXPECT_EQ(keyword("End_If"), Kw::endif);
  EXPECT_EQ(keyword("To"), Kw::to);
  EXPECT_EQ(keyword("def_evt_var"), Kw::def_evt_var);
  EXPECT_EQ(keyword("MainLoop"), Kw::none);
  EXPECT_EQ(keyword("a"), Kw::none);
}

TEST(BasicLexer, DecimalAndHexNumbersWrapTo32Bits) {
  struct Case {
    const char* text;
    std::uint32_t value;
  };
  for (const Case& c :
       {Case{"10000", 10000}, Case{"0", 0}, Case{"$7F", 0x7F}, Case{"$00010000", 0x10000},
        Case{"$ffffffff", 0xFFFFFFFF}, Case{"4294967295", 0xFFFFFFFF}, Case{"2147483648", 0x80000000}}) {
    const auto l = lex_line(c.text);
    ASSERT_TRUE(l.error.empty()) << c.text << ": " << l.error;
    ASSERT_EQ(l.tokens.size(), 1U) << c.text;
    EXPECT_EQ(l.tokens[0].kind, Tok::number) << c.text;
    EXPECT_EQ(l.tokens[0].value, c.value) << c.text;
  }
}

TEST(BasicLexer, ObjectReferencesTakeBothSubIndexForms) {
  struct Case {
    const char* text;
    std::uint16_t index;
    std::uint8_t sub;
  };
  for (const Case& c : {Case{"$607A.00", 0x607A, 0}, Case{"$2310.$10", 0x2310, 0x10}, Case{"$3005.1A", 0x3005, 0x1A},
                        Case{"$2310.10", 0x2310, 0x10}, Case{"$6040.$00", 0x6040, 0}, Case{"$1.2", 1, 2}}) {
    const auto l = lex_line(c.text);
    ASSERT_TRUE(l.error.empty()) << c.text << ": " << l.error;
    ASSERT_EQ(l.tokens.size(), 1U);
    EXPECT_EQ(l.tokens[0].kind, Tok::objref) << c.text;
    EXPECT_EQ(l.tokens[0].index, c.index) << c.text;
    EXPECT_EQ(l.tokens[0].sub, c.sub) << c.text;
  }
}

TEST(BasicLexer, LabelsOnlyAtTheStartOfALine) {
  const auto l = lex_line("  :Main_Loop2 ' comment");
  ASSERT_TRUE(l.error.empty());
  ASSERT_EQ(l.tokens.size(), 1U);
  EXPECT_EQ(l.tokens[0].kind, Tok::label);
  EXPECT_EQ(l.tokens[0].text, "Main_Loop2");
  EXPECT_FALSE(lex_line("a = 1 :X").error.empty());
  EXPECT_FALSE(lex_line(":").error.empty());
  EXPECT_FALSE(lex_line(": X").error.empty());
}

TEST(BasicLexer, IfParenthesisWithoutSpaceAndOperators) {
  EXPECT_EQ(kinds("IF(y = 0) THEN"),
            (std::vector<Tok>{Tok::word, Tok::lparen, Tok::word, Tok::eq, Tok::number, Tok::rparen, Tok::word}));
  EXPECT_EQ(lex_line("IF(y").tokens[0].kw, Kw::if_);
  EXPECT_EQ(kinds("<> <= >= < > = + - * / % & | ~ ( ) ,"),
            (std::vector<Tok>{Tok::ne, Tok::le, Tok::ge, Tok::lt, Tok::gt, Tok::eq, Tok::plus, Tok::minus, Tok::star,
                              Tok::slash, Tok::percent, Tok::amp, Tok::pipe, Tok::tilde, Tok::lparen, Tok::rparen,
                              Tok::comma}));
  EXPECT_EQ(kinds("a<>b"), (std::vector<Tok>{Tok::word, Tok::ne, Tok::word}));
  EXPECT_EQ(kinds("-1"), (std::vector<Tok>{Tok::minus, Tok::number}));  // minus is the unary operator
}

TEST(BasicLexer, MalformedTokensAreErrors) {
  for (const char* bad : {"a = 99999999999", "a = $100000000", "a = $", "a = $G", "a = 1.5", "a = 12ab",
                          "SETOBJ $10000.00 = 1", "SETOBJ $6040.100 = 1", "SETOBJ $6040. = 1", "SETOBJ $6040.00x = 1",
                          "a = 1 # 2", "a = \"x\"", "a = 1 \x01", "a = \xC3\xBC"}) {
    const auto l = lex_line(bad);
    EXPECT_FALSE(l.error.empty()) << bad;
    EXPECT_TRUE(l.tokens.empty()) << bad;
  }
}

TEST(BasicLexer, DescribeNamesTheToken) {
  const auto l = lex_line("THEN");
  EXPECT_EQ(describe(l.tokens[0]), "'THEN'");
  EXPECT_EQ(describe(Token{}), "end of line");
}

}  // namespace
}  // namespace mcemu::basic
