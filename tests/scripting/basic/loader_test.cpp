// The loader (faulhaber.md §9.1, §9.2, §9.5): every load error with its line, the forms that must
// load (one-line and block IF, END_IF, IF( without a space, labels, FOR/NEXT), the 4096-byte limit
// and the compiled form's statement count.
#include "scripting/basic/loader.hpp"

#include <gtest/gtest.h>

#include <string>

namespace mcemu::basic {
namespace {

std::string nested_ifs(int depth) {
  std::string s;
  for (int i = 0; i < depth; ++i) s += "IF a THEN\n";
  s += "b = 1\n";
  for (int i = 0; i < depth; ++i) s += "ENDIF\n";
  return s;
}

LoadError error_of(std::string_view text) {
  auto r = load(text);
  if (auto* e = std::get_if<LoadError>(&r)) return *e;
  return LoadError{0, "(loaded)"};
}

struct BadCase {
  const char* name;
  std::string text;
  std::uint32_t line;
  const char* message_part;
};

class BasicLoadErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(BasicLoadErrors, ReportLineAndReason) {
  const auto& c = GetParam();
  auto r = load(c.text);
  ASSERT_TRUE(std::holds_alternative<LoadError>(r)) << c.name << " loaded";
  const auto& e = std::get<LoadError>(r);
  EXPECT_EQ(e.line, c.line) << c.name << ": " << e.message;
  EXPECT_NE(e.message.find(c.message_part), std::string::npos) << c.name << ": " << e.message;
}

const BadCase k_bad[] = {
    // structure
    {"nesting16", nested_ifs(16), 16, "nested deeper than 15"},
    {"if_without_endif", "a = 1\nIF a THEN\nb = 1\n", 2, "IF without ENDIF"},
    {"inner_if_without_endif", "IF a THEN\nIF b THEN\nENDIF\n", 1, "IF without ENDIF"},
    {"endif_without_if", "a = 1\nENDIF\n", 2, "ENDIF without IF"},
    {"else_without_if", "ELSE\n", 1, "ELSE without IF"},
    {"elseif_without_if", "' x\nELSEIF a THEN\n", 2, "ELSEIF without IF"},
    {"elseif_after_else", "IF a THEN\nELSE\nELSEIF b THEN\nENDIF\n", 3, "ELSEIF after ELSE"},
    {"second_else", "IF a THEN\nELSE\nELSE\nENDIF\n", 3, "a second ELSE"},
    {"one_line_if_opens_block", "IF a THEN b = 1\nELSE\nb = 2\n", 1, "IF without ENDIF"},
    {"for_without_next", "FOR i = 1 TO 3\na = i\n", 1, "FOR without NEXT"},
    {"next_without_for", "a = 1\nNEXT\n", 2, "NEXT without FOR"},
    {"next_wrong_var", "FOR i = 1 TO 3\nNEXT j\n", 2, "NEXT j does not match FOR i"},
    {"next_inside_if", "FOR i = 1 TO 3\nIF a THEN\nNEXT\nENDIF\n", 3, "NEXT inside the IF block of line 2"},
    {"endif_inside_for", "IF a THEN\nFOR i = 1 TO 3\nENDIF\nNEXT\n", 3, "inside the FOR loop of line 2"},
    {"block_statement_inline", "IF a THEN FOR i = 1 TO 2\n", 1, "cannot follow THEN"},
    {"else_with_if_inline", "IF a THEN\nELSE IF b THEN c = 1\nENDIF\n", 2, "cannot follow ELSE"},
    // labels and the GOTO rule
    {"unknown_goto", "GOTO Nowhere\n", 1, "unknown label 'nowhere'"},
    {"unknown_gosub", "a = 1\nGOSUB Sub\n", 2, "unknown label 'sub'"},
    {"unknown_event_label", "EN_EVT $1, Handler\n", 1, "unknown label 'handler'"},
    {"duplicate_label", ":Init\na = 1\n:INIT\n", 3, "duplicate label 'INIT' (first at line 1)"},
    {"goto_out_of_block", "IF a THEN\nGOTO Out\nENDIF\n:Out\n", 2, "leaves an IF block"},
    {"goto_out_of_else", ":Top\nIF a THEN\nb = 1\nELSE\nGOTO Top\nENDIF\n", 5, "leaves an IF block"},
    {"one_line_goto_out_of_block", "IF a THEN\nIF b THEN GOTO Out\nENDIF\n:Out\n", 2, "leaves an IF block"},
    {"goto_into_block", "GOTO In\nIF a THEN\n:In\nb = 1\nENDIF\n", 1, "jumps into an IF block"},
    {"goto_other_branch", "IF a THEN\nGOTO B\nELSE\n:B\nENDIF\n", 2, "leaves its IF branch for another"},
    {"goto_other_block", "IF a THEN\nGOTO B\nENDIF\nIF c THEN\n:B\nENDIF\n", 2, "leaves its IF branch for another"},
    {"block_opening_one_line_goto", "IF a THEN GOTO X\nELSE\nENDIF\n:X\n", 1, "leaves an IF block"},
    {"label_with_statement", ":Init a = 1\n", 1, "holds only the label"},
    // syntax
    {"missing_value", "a = \n", 1, "expected a value"},
    {"dangling_operator", "a = 1 +\n", 1, "expected a value"},
    {"missing_paren", "a = (1 + 2\n", 1, "expected ')'"},
    {"extra_token", "a = b c\n", 1, "unexpected 'c'"},
    {"unknown_statement", "PRINT a\n", 1, "unknown statement 'PRINT'"},
    {"long_variable_name", "a = foo + 1\n", 1, "unknown name 'foo'"},
    {"keyword_as_value", "a = THEN\n", 1, "expected a value"},
    {"missing_then", "IF a = 1\nENDIF\n", 1, "expected THEN"},
    {"missing_to", "FOR i = 1 3\nNEXT\n", 1, "expected TO"},
    {"setobj_without_ref", "SETOBJ 6040 = 1\n", 1, "expected an object reference"},
    {"setobj_without_sub", "SETOBJ $6040 = 1\n", 1, "expected an object reference"},
    {"getobj_without_ref", "a = GETOBJ\n", 1, "expected an object reference"},
    {"bare_objref", "a = $6041.00\n", 1, "needs GETOBJ"},
    {"assignment_without_eq", "a 1\n", 1, "expected '='"},
    {"en_evt_without_label", "EN_EVT $1\n", 1, "expected ','"},
    {"save_without_vars", "SAVE\n", 1, "expected a variable"},
    {"save_bad_list", "SAVE a, 1\n", 1, "expected a variable"},
    {"def_tim_var_number", "DEF_TIM_VAR 5\n", 1, "expected a variable"},
    {"then_alone", "THEN\n", 1, "cannot start a statement"},
    {"lexical", "a = 1\nb = 1.5\n", 2, "malformed number"},
    {"too_deep", "a = " + std::string(70, '(') + "1" + std::string(70, ')') + "\n", 1, "nested too deeply"},
    {"unary_too_deep", "a = " + std::string(70, '-') + "1\n", 1, "nested too deeply"},
    {"not_in_comparison", "a = 1 = NOT b\n", 1, "expected a value"},
    // line numbers with every line end
    {"crlf_lines", "a = 1\r\n\r\nb = \r\n", 3, "expected a value"},
    {"cr_lines", "a = 1\r'x\rb = \r", 3, "expected a value"},
    // size
    {"size_4097", "a = 1\n" + std::string(4097 - 6, '\''), 0, "4097 bytes"},
};

INSTANTIATE_TEST_SUITE_P(All, BasicLoadErrors, ::testing::ValuesIn(k_bad));

TEST(BasicLoader, FifteenNestedIfsLoad) { EXPECT_TRUE(std::holds_alternative<Program>(load(nested_ifs(15)))); }

TEST(BasicLoader, Exactly4096BytesLoad) {
  std::string text = "a = 1\n";
  text += std::string(4096 - text.size(), '\'');
  ASSERT_EQ(text.size(), 4096U);
  EXPECT_TRUE(std::holds_alternative<Program>(load(text)));
}

TEST(BasicLoader, FormsThatLoad) {
  for (const char* ok : {
           "",
           "' only a comment\n\n   \n",
           "IF(y = 0) THEN\nb = 1\nELSEIF(y = 1) THEN\nb = 2\nELSE\nb = 3\nEND_IF\n",
           ":Loop\nIF a = 1 THEN GOTO Loop\n",  // top-level one-line IF with GOTO
           "IF (z = 1) THEN GOSUB Z1\nELSEIF(z = 2) THEN GOSUB Z2\nENDIF\n:Z1\nRETURN\n:Z2\nReturn\n",
           "IF a THEN\n:Again\nb = b + 1\nIF b < 3 THEN GOTO Again\nENDIF\n",  // GOTO within one branch
           "IF a THEN b = 1\n' comment\n\nELSE c = 2\nENDIF\n",                // comment lines before ELSE
           "FOR i = 1 TO 10 STEP 2\nFOR j = 1 To 2\nNEXT\nNEXT i\n",
           "GOTO In\nFOR i = 1 TO 3\n:In\nNEXT\n",  // the GOTO rule concerns IF blocks only
           "DEF_EVT_VAR e\nEN_EVT $00010000, OverTemp\n:OverTemp\nRET_EVT\n",
           "DEF_TIM_VAR t\nSTART_TIM 10000\nDEF_CYC_VAR c\nSTART_CYC\nSTOP_CYC\nSAVE a, b, c\nLOAD a\n",
           "SETOBJ $2310.$10 = 0\nSETOBJ $3005.1A = GETOBJ $3005.01\n",
           ":Next\nGOTO next\n",  // a label may be spelt like a keyword
           "A = 1\nz = a + Z\n",
       }) {
    auto r = load(ok);
    EXPECT_TRUE(std::holds_alternative<Program>(r))
        << ok << "\n→ line " << error_of(ok).line << ": " << error_of(ok).message;
  }
}

TEST(BasicLoader, StatementsCountLinesNotLabelsOrComments) {
  auto r = load(":Init\n' c\na = 1\n\nIF a THEN b = 2\nIF a THEN\nc = 3\nELSE\nENDIF\nGOTO Init\n");
  ASSERT_TRUE(std::holds_alternative<Program>(r));
  const auto& p = std::get<Program>(r);
  // a = 1; one-line IF (with its statement); IF; c = 3; GOTO — ELSE, ENDIF and the label are free
  EXPECT_EQ(p.statements, 5U);
  EXPECT_EQ(p.lines, 10U);
  EXPECT_EQ(p.code.back().op, Op::end);
}

}  // namespace
}  // namespace mcemu::basic
