// Expressions (faulhaber.md §9.4) as the interpreter evaluates them: precedence (bitwise above
// comparisons [choice]), wrap-around on signed 32 bits, `/` truncating toward zero, `%` with the
// dividend's sign, comparisons, NOT/AND/OR with both operands evaluated, GETOBJ's type extension,
// and the run-time errors of expressions.
#include <gtest/gtest.h>

#include <string>

#include "tests/scripting/basic/harness.hpp"

namespace mcemu::basic {
namespace {

using test::Rig;

struct ExprCase {
  const char* expr;
  std::int32_t value;
};

// Variables preset for every case: a = 5, s = $40, m = -7.
class BasicExpressions : public ::testing::TestWithParam<ExprCase> {};

TEST_P(BasicExpressions, Evaluate) {
  const auto& c = GetParam();
  Rig rig;
  rig.set_var('a', 5);
  rig.set_var('s', 0x40);
  rig.set_var('m', -7);
  rig.set(0x6060, 0, -3);
  rig.set(0x2400, 0x04, 0xFFFFFFF0);
  rig.set(0x6041, 0, 0x0237);
  rig.set(0x2310, 0x03, -2);
  rig.start(std::string("r = ") + c.expr + "\n");
  rig.step();
  ASSERT_EQ(rig.interp->state(), RunState::finished) << c.expr << ": " << rig.interp->error().message;
  EXPECT_EQ(rig.var('r'), c.value) << c.expr;
}

const ExprCase k_cases[] = {
    // precedence, high → low: unary; * / %; + -; &; |; comparisons; NOT; AND; OR
    {"2 + 3 * 4", 14},
    {"(2 + 3) * 4", 20},
    {"-2 * 3", -6},
    {"- 2 + 3", 1},
    {"-a * -a", 25},
    {"~0", -1},
    {"~5 + 1", -5},
    {"2 * 3 % 4", 2},
    {"100 / 10 / 5", 2},
    {"10 - 3 - 2", 5},
    {"1 + 2 & 6", 2},
    {"6 & 3 | 8", 10},
    {"1 | 2 & 0", 1},
    {"5 & 4 = 4", 1},      // (5 & 4) = 4 [choice: bitwise above comparisons]
    {"s & $6F = $40", 1},  // AN165 writes ((s & $6F) = $40)
    {"1 | 2 = 3", 1},
    {"1 < 2 = 1", 1},  // comparisons are left-associative: (1 < 2) = 1
    {"NOT 0", 1},
    {"NOT 5", 0},
    {"NOT 1 = 2", 1},  // NOT (1 = 2)
    {"NOT NOT 7", 1},
    {"1 = 1 AND 2 = 3", 0},
    {"1 = 1 OR 2 = 3", 1},
    {"0 OR 1 AND 0", 0},
    {"1 OR 0 AND 0", 1},
    {"NOT 0 AND 0", 0},
    {"3 AND 4", 1},
    {"0 OR -7", 1},
    {"0 AND 0", 0},
    {"(a = 5) AND (s > 0)", 1},
    // comparisons (signed)
    {"3 < 5", 1},
    {"5 < 3", 0},
    {"3 <= 3", 1},
    {"4 >= 5", 0},
    {"4 > -5", 1},
    {"4 <> 4", 0},
    {"4 <> 5", 1},
    {"4 = 4", 1},
    {"-1 < 0", 1},
    {"$FFFFFFFF < 0", 1},
    {"m < a", 1},
    // wrap-around on 32 bits
    {"2147483647 + 1", -2147483647 - 1},
    {"-2147483648 - 1", 2147483647},
    {"65536 * 65536", 0},
    {"$7FFFFFFF * 2", -2},
    {"-(-2147483648)", -2147483647 - 1},
    {"2147483648", -2147483647 - 1},
    {"$FFFFFFFF", -1},
    {"$80000000 / -1", -2147483647 - 1},
    {"$80000000 % -1", 0},
    {"~$7FFFFFFF", -2147483647 - 1},
    // division truncates toward zero; the remainder has the dividend's sign
    {"7 / 2", 3},
    {"-7 / 2", -3},
    {"7 / -2", -3},
    {"-7 / -2", 3},
    {"m / 2", -3},
    {"7 % 3", 1},
    {"-7 % 3", -1},
    {"7 % -3", 1},
    {"-7 % -3", -1},
    {"m % 4", -3},
    // variables (upper case is the same variable) and GETOBJ
    {"a + A", 10},
    {"GETOBJ $6060.00", -3},          // INTEGER8 extended
    {"GETOBJ $2310.03", -2},          // INTEGER16 extended
    {"GETOBJ $2400.04", -16},         // UNSIGNED32 reinterpreted as signed
    {"GETOBJ $6041.00 & $7F", 0x37},  // UNSIGNED16
    {"GETOBJ $3005.01 + 1", 6},       // the variable a through its object
    {"GETOBJ $3005.00", 26},
    {"(GETOBJ $6041.00 & $0200) > 0", 1},
};

INSTANTIATE_TEST_SUITE_P(Table, BasicExpressions, ::testing::ValuesIn(k_cases));

struct ErrorCase {
  const char* expr;
  const char* message_part;
  od::AbortCode code;
};

class BasicExpressionErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(BasicExpressionErrors, StopTheProgramWithLineAndCode) {
  const auto& c = GetParam();
  Rig rig;
  rig.start(std::string("a = 1\n' comment\nr = ") + c.expr + "\nb = 1\n");
  rig.step();
  ASSERT_EQ(rig.interp->state(), RunState::error) << c.expr;
  EXPECT_EQ(rig.interp->error().line, 3U);
  EXPECT_EQ(rig.interp->line(), 3U);
  EXPECT_NE(rig.interp->error().message.find(c.message_part), std::string::npos) << rig.interp->error().message;
  EXPECT_EQ(rig.interp->error().code, c.code);
  EXPECT_EQ(rig.var('b'), 0) << "nothing after the failing line ran";
  const auto errors = rig.of_kind(EventKind::error);
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_EQ(errors[0].line, 3U);
  EXPECT_EQ(errors[0].code, c.code);
}

const ErrorCase k_errors[] = {
    {"1 / 0", "division by zero", od::AbortCode::none},
    {"a % (a - 1)", "remainder of a division by zero", od::AbortCode::none},
    {"GETOBJ $1234.00", "GETOBJ 1234h.00: 06020000", od::AbortCode::no_object},
    {"GETOBJ $3005.1B", "06090011", od::AbortCode::no_sub},
    {"GETOBJ $1008.00", "06070010", od::AbortCode::type_mismatch},    // a string entry
    {"0 AND GETOBJ $1234.00", "06020000", od::AbortCode::no_object},  // both operands are evaluated
    {"1 OR 1 / 0", "division by zero", od::AbortCode::none},
};

INSTANTIATE_TEST_SUITE_P(Table, BasicExpressionErrors, ::testing::ValuesIn(k_errors));

}  // namespace
}  // namespace mcemu::basic
