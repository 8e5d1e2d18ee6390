#include "protocols/line/line_assembler.hpp"

#include <gtest/gtest.h>

namespace mcemu::line {
namespace {

int drop_controls(unsigned char c) {
  if (c == '\t') return ' ';
  if (c < 0x20 || c == 0x7F) return -1;
  return c;
}

struct Case {
  const char* name;
  std::string input;
  std::vector<std::pair<std::string, bool>> lines;  // text, overlong
  std::size_t max = 10;
  ByteFilter filter = keep_all;
};

class Assembler : public ::testing::TestWithParam<Case> {};

std::vector<std::pair<std::string, bool>> run(const Case& c, std::size_t chunk) {
  LineAssembler a(c.max, c.filter);
  std::vector<Line> out;
  for (std::size_t i = 0; i < c.input.size(); i += chunk) a.feed(std::string_view(c.input).substr(i, chunk), out);
  std::vector<std::pair<std::string, bool>> got;
  for (auto& l : out) got.emplace_back(l.text, l.overlong);
  return got;
}

TEST_P(Assembler, SameResultForEverySplit) {
  const auto& c = GetParam();
  EXPECT_EQ(run(c, c.input.size() + 1), c.lines);
  // split at every byte offset into two parts, and byte by byte
  for (std::size_t cut = 0; cut <= c.input.size(); ++cut) {
    LineAssembler a(c.max, c.filter);
    std::vector<Line> out;
    a.feed(std::string_view(c.input).substr(0, cut), out);
    a.feed(std::string_view(c.input).substr(cut), out);
    std::vector<std::pair<std::string, bool>> got;
    for (auto& l : out) got.emplace_back(l.text, l.overlong);
    EXPECT_EQ(got, c.lines) << "cut at " << cut;
  }
  EXPECT_EQ(run(c, 1), c.lines);
}

INSTANTIATE_TEST_SUITE_P(Rules, Assembler,
                         ::testing::Values(Case{"cr", "TP\r", {{"TP", false}}}, Case{"lf", "TP\n", {{"TP", false}}},
                                           Case{"crlf_is_one", "TP\r\nTS\r\n", {{"TP", false}, {"TS", false}}},
                                           Case{"lfcr_is_two", "O\n\r", {{"O", false}, {"", false}}},
                                           Case{"empty_lines", "\r\r", {{"", false}, {"", false}}},
                                           Case{"unterminated_rest_kept_back", "TP\rTS", {{"TP", false}}},
                                           Case{"overlong", "0123456789AB\rX\r", {{"0123456789", true}, {"X", false}}},
                                           Case{"exactly_max", "0123456789\r", {{"0123456789", false}}},
                                           Case{"controls_removed_before_counting",
                                                "01234\x01\x02\x03"
                                                "56789\r",
                                                {{"0123456789", false}},
                                                10,
                                                drop_controls},
                                           Case{"tab_becomes_space", "OW\t1\r", {{"OW 1", false}}, 10, drop_controls},
                                           Case{"binary_kept_by_keep_all",
                                                std::string("t\x00\xff\r", 4),
                                                {{std::string("t\x00\xff", 3), false}}}),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(AssemblerLimits, MemoryStaysBoundedWithoutTerminator) {
  LineAssembler a(64, keep_all);
  for (int i = 0; i < 10000; ++i) EXPECT_TRUE(a.feed(std::string(100, 'A')).empty());
  auto lines = a.feed("\r");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_TRUE(lines[0].overlong);
  EXPECT_EQ(lines[0].text.size(), 64u);
}

TEST(AssemblerLimits, ResetForgetsPartialLineAndPendingCr) {
  LineAssembler a(64, keep_all);
  a.feed("AB\r");
  a.feed("CD");
  EXPECT_TRUE(a.has_partial());
  a.reset();
  EXPECT_FALSE(a.has_partial());
  auto lines = a.feed("\nX\r");
  ASSERT_EQ(lines.size(), 2u) << "after reset an LF is a line end of its own";
  EXPECT_EQ(lines[0].text, "");
  EXPECT_EQ(lines[1].text, "X");
}

// The raw bytes of each line for the trace (refgo.md §13): unfiltered, with the terminator that
// ended it, bounded for an over-long line; the same for every split.
TEST(AssemblerRaw, KeepsTheBytesAsReceived) {
  const std::string input = "OW\t1\x01\r\nTS\n" + std::string(30, 'X') + "\r";
  for (std::size_t chunk = 1; chunk <= input.size(); ++chunk) {
    LineAssembler a(10, drop_controls);
    std::vector<Line> out;
    for (std::size_t i = 0; i < input.size(); i += chunk) a.feed(std::string_view(input).substr(i, chunk), out);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[0].text, "OW 1");
    EXPECT_EQ(out[0].raw, "OW\t1\x01\r") << "the LF after CR belongs to no line";
    EXPECT_EQ(out[1].raw, "TS\n");
    EXPECT_TRUE(out[2].overlong);
    EXPECT_EQ(out[2].raw, std::string(11, 'X')) << "at most max + 1 bytes";
  }
}

}  // namespace
}  // namespace mcemu::line
