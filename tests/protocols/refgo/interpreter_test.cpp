// The built-in interpreter against a real MC349 dictionary: object access, parameters, status
// answers and every error form of refgo.md §9.4/§10; vectors of §14.2, §14.4 and §14.5 that do not
// need the drive core to move.
#include "protocols/refgo/interpreter.hpp"

#include <gtest/gtest.h>

#include <regex>

#include "protocols/refgo/command.hpp"
#include "tests/protocols/refgo/refgo_fixture.hpp"

namespace mcemu::refgo {
namespace {

// Object values are set directly here (internal writes); the core overwrites the ones it owns
// only at its next step, which these tests do not take.
class InterpreterTest : public ::testing::Test {
 protected:
  std::string run(std::string_view line) {
    auto r = d_.in.execute(line);
    EXPECT_TRUE(r.has_value()) << line;
    return r.value_or("<pending>");
  }
  void set(std::uint16_t i, std::uint8_t s, std::int64_t v) { d_.set(i, s, v); }
  std::int64_t get(std::uint16_t i, std::uint8_t s) { return d_.get(i, s); }

  test::Drive d_;
  od::ObjectDictionary& od_ = d_.od;
  Interpreter& in_ = d_.in;
};

struct Vector {
  std::string line;   // as delivered by the line assembler
  std::string reply;  // exact bytes
};

class Vectors : public InterpreterTest, public ::testing::WithParamInterface<Vector> {};

TEST_P(Vectors, ByteExact) {
  set(0x607C, 0, -10);
  set(0x3410, 1, 4242);
  EXPECT_EQ(run(GetParam().line), GetParam().reply);
}

INSTANTIATE_TEST_SUITE_P(
    Spec, Vectors,
    ::testing::Values(
        // §14.5
        Vector{"", ">"}, Vector{"  ", ">"}, Vector{"XYZ", ">"}, Vector{"TT", ">"}, Vector{"TV", ">"},
        Vector{"SCRV20", ">"}, Vector{"123", ">"}, Vector{"?", ">"}, Vector{"\xFFTP", ">"}, Vector{"@S", ">"},
        Vector{"OW6041,0,5", "OW6041,0,5\r\nOW6041,0,5,ERROR,06010002h\r\n>"},
        Vector{"OR1234,0", "OR1234,0\r\nOR1234,0,ERROR,06020000h\r\n>"},
        Vector{"OR6041,9", "OR6041,9\r\nOR6041,9,ERROR,06090011h\r\n>"},
        Vector{"OW6060,0,99", "OW6060,0,99\r\nOW6060,0,99,ERROR,06090030h\r\n>"},
        Vector{"OW340B,1,300", "OW340B,1,300\r\nOW340B,1,300,ERROR,06090031h\r\n>"},
        Vector{"OW6040,0,X", "OW6040,0,X\r\nOW6040,0,X,ERROR,08000000h\r\n>"},
        Vector{"OR607C,0,h", "OR607C,0,H\r\nOR607C,0,fffffff6h\r\n>"},
        Vector{"OR1008,0", "OR1008,0\r\nOR1008,0,MC349_ETH_RE\r\n>"},
        Vector{"OR1008,0,h", "OR1008,0,H\r\nOR1008,0,MC349_ETH_RE\r\n>"},
        Vector{"SO7", "SO7\r\nSO7,ERROR,06090030h\r\n>"}, Vector{"SO 7", "SO 7\r\nSO 7,ERROR,06090030h\r\n>"},
        Vector{"OR1234,0,h", "OR1234,0,H\r\nOR1234,0,ERROR,06020000h\r\n>"},
        Vector{"SP4294967296", "SP4294967296\r\nSP4294967296,ERROR,06090030h\r\n>"},
        // §14.4 (object values set by the fixture)
        Vector{"OW6067,0,100", "OW6067,0,100\r\nOW6067,0,100,OK\r\n>"},
        Vector{"OW 60FE,1,65536", "OW 60FE,1,65536\r\nOW 60FE,1,65536,OK\r\n>"},
        Vector{"OR3410h,1h", "OR3410H,1H\r\nOR3410H,1H,4242\r\n>"},
        Vector{"OW3510H,1H,65536", "OW3510H,1H,65536\r\nOW3510H,1H,65536,OK\r\n>"},
        // §14.1 rows 3–10 (parameters)
        Vector{"OW6091,1,1", "OW6091,1,1\r\nOW6091,1,1,OK\r\n>"},
        Vector{"OW6092,1,360", "OW6092,1,360\r\nOW6092,1,360,OK\r\n>"},
        Vector{"OW609A,0,400", "OW609A,0,400\r\nOW609A,0,400,OK\r\n>"},
        Vector{"OW607C,0,-10", "OW607C,0,-10\r\nOW607C,0,-10,OK\r\n>"},
        // other error forms of §9.4 / §10
        Vector{"OR6041", "OR6041\r\nOR6041,ERROR,08000000h\r\n>"},
        Vector{"OR6041,0,X", "OR6041,0,X\r\nOR6041,0,X,ERROR,08000000h\r\n>"},
        Vector{"OR6041,0,h,1", "OR6041,0,H,1\r\nOR6041,0,H,1,ERROR,08000000h\r\n>"},
        Vector{"OR123456789,0", "OR123456789,0\r\nOR123456789,0,ERROR,08000000h\r\n>"},
        Vector{"OR10000,0", "OR10000,0\r\nOR10000,0,ERROR,06020000h\r\n>"},
        Vector{"OR6041,100", "OR6041,100\r\nOR6041,100,ERROR,06090011h\r\n>"},
        Vector{"OW10000,0,1", "OW10000,0,1\r\nOW10000,0,1,ERROR,06020000h\r\n>"},
        Vector{"OW6040,100,1", "OW6040,100,1\r\nOW6040,100,1,ERROR,06090011h\r\n>"},
        Vector{"OW6040,0", "OW6040,0\r\nOW6040,0,ERROR,08000000h\r\n>"},
        Vector{"OW6040,0,1,2", "OW6040,0,1,2\r\nOW6040,0,1,2,ERROR,08000000h\r\n>"},
        Vector{"OW6040,0,-1H", "OW6040,0,-1H\r\nOW6040,0,-1H,ERROR,08000000h\r\n>"},
        Vector{"OW6040,0,99999999999999999999",
               "OW6040,0,99999999999999999999\r\nOW6040,0,99999999999999999999,ERROR,08000000h\r\n>"},
        Vector{"OW1008,0,1", "OW1008,0,1\r\nOW1008,0,1,ERROR,06010002h\r\n>"},
        Vector{"OW340B,1,-1", "OW340B,1,-1\r\nOW340B,1,-1,ERROR,06090032h\r\n>"},
        Vector{" ow6040,0,x ", " OW6040,0,X \r\nOW6040,0,X,ERROR,08000000h\r\n>"},
        Vector{"OR60A4,0", "OR60A4,0\r\nOR60A4,0,ERROR,06020000h\r\n>"},
        Vector{"ACV100", "ACV100\r\nACV100,ERROR,06020000h\r\n>"}, Vector{"TP5", "TP5\r\nTP5,ERROR,08000000h\r\n>"},
        Vector{"TP\xFF", "TP\xFF\r\nTP\xFF,ERROR,08000000h\r\n>"},
        Vector{"TPSR 1", "TPSR 1\r\nTPSR 1,ERROR,08000000h\r\n>"}, Vector{"TS x", "TS X\r\nTS X,ERROR,08000000h\r\n>"},
        Vector{"SP", "SP\r\nSP,ERROR,08000000h\r\n>"}, Vector{"SP-1", "SP-1\r\nSP-1,ERROR,06090030h\r\n>"},
        Vector{"SP12X", "SP12X\r\nSP12X,ERROR,08000000h\r\n>"},
        Vector{"SP 1.5", "SP 1.5\r\nSP 1.5,ERROR,08000000h\r\n>"},
        Vector{"AC00000000001", "AC00000000001\r\nAC00000000001,ERROR,08000000h\r\n>"},
        Vector{"PO2147483648", "PO2147483648\r\nPO2147483648,ERROR,06090030h\r\n>"},
        Vector{"WA-2147483649", "WA-2147483649\r\nWA-2147483649,ERROR,06090030h\r\n>"},
        Vector{"RW2147483648", "RW2147483648\r\nRW2147483648,ERROR,06090030h\r\n>"},
        Vector{"WT-1", "WT-1\r\nWT-1,ERROR,06090030h\r\n>"}, Vector{"CO0", "CO0\r\nCO0,ERROR,06090030h\r\n>"},
        Vector{"CO", "CO\r\nCO,ERROR,08000000h\r\n>"}, Vector{"TI0", "TI0\r\nTI0,ERROR,06090030h\r\n>"},
        Vector{"TI11", "TI11\r\nTI11,ERROR,06090030h\r\n>"}, Vector{"TI1", "TI1\r\n0\r\n>"},
        Vector{"TI", "TI\r\n0000\r\n>"}, Vector{"ti  ", "TI  \r\n0000\r\n>"}));

// find_command compares packed integers: every word of the table finds its own row, and words
// that only share a prefix, differ in length or in one letter find nothing.
TEST(FindCommand, ExactWordsOnly) {
  for (const CommandRow& row : command_table()) {
    const CommandRow* found = find_command(row.word);
    ASSERT_NE(found, nullptr) << row.word;
    EXPECT_EQ(found->word, row.word);
  }
  for (std::string_view miss : {"", "T", "TPS", "TPSRX", "GG", "GWW", "PW", "PWCX", "RE", "REFX", "AC V", "ACVV", "tp",
                                "XYZ", "ABCDE", "ZZZZ", "OX", "W"}) {
    EXPECT_EQ(find_command(miss), nullptr) << miss;
  }
  EXPECT_NE(find_command("G"), find_command("GW"));
  EXPECT_NE(find_command("TP"), find_command("TPSR"));
}

TEST_F(InterpreterTest, ObjectRoundTripLikeThe2021Log) {
  // MAN §4.4.3 rows 12–14 and the DEMO extract of 21.10.2021 13:05.
  EXPECT_EQ(run("OW3511,8,110"), "OW3511,8,110\r\nOW3511,8,110,OK\r\n>");
  EXPECT_EQ(run("OR3511,8"), "OR3511,8\r\nOR3511,8,110\r\n>");
  EXPECT_EQ(run("OW3511,8,120"), "OW3511,8,120\r\nOW3511,8,120,OK\r\n>");
  EXPECT_EQ(run("OR3511,8"), "OR3511,8\r\nOR3511,8,120\r\n>");
  EXPECT_EQ(get(0x3511, 8), 120);
}

TEST_F(InterpreterTest, OwAcceptsHexValuesAndTwosComplementForU32) {
  EXPECT_EQ(run("OW6081,0,80h"), "OW6081,0,80H\r\nOW6081,0,80H,OK\r\n>");
  EXPECT_EQ(get(0x6081, 0), 0x80);
  EXPECT_EQ(run("OW6081,0,0x100"), "OW6081,0,0X100\r\nOW6081,0,0X100,OK\r\n>");
  EXPECT_EQ(get(0x6081, 0), 0x100);
  EXPECT_EQ(run("OW340F,1,-1"), "OW340F,1,-1\r\nOW340F,1,-1,OK\r\n>");
  EXPECT_EQ(run("OR340F,1"), "OR340F,1\r\nOR340F,1,4294967295\r\n>");
  EXPECT_EQ(run("OR340F,1,h"), "OR340F,1,H\r\nOR340F,1,ffffffffh\r\n>");
}

TEST_F(InterpreterTest, OrHexAndDecimalFormats) {
  set(0x607C, 0, 0);
  EXPECT_EQ(run("OR607C,0,h"), "OR607C,0,H\r\nOR607C,0,0h\r\n>");
  EXPECT_EQ(run("OR 607C , 0 , h "), "OR 607C , 0 , H \r\nOR 607C , 0,0h\r\n>");
  set(0x607C, 0, -10);
  EXPECT_EQ(run("OR607C,0"), "OR607C,0\r\nOR607C,0,-10\r\n>");
  EXPECT_EQ(run("OR1018,1"), "OR1018,1\r\nOR1018,1,1339\r\n>");
}

TEST_F(InterpreterTest, StatusAnswersFollowTheObjects) {
  set(0x6041, 0, 0x0427);
  EXPECT_EQ(run("TPSR"), "TPSR\r\n0000010a\r\n>");
  EXPECT_EQ(run("TS"), "TS\r\n1\r\n>");
  EXPECT_EQ(run("OR6041,0,h"), "OR6041,0,H\r\nOR6041,0,427h\r\n>");
  set(0x6041, 0, 0x1327);
  EXPECT_EQ(run("TPSR"), "TPSR\r\n00000106\r\n>");
  EXPECT_EQ(run("TS"), "TS\r\n2\r\n>");
  set(0x6041, 0, 0x0228);
  EXPECT_EQ(run("TS"), "TS\r\n9\r\n>");
  set(0x6041, 0, 0x0240);
  EXPECT_EQ(run("TS"), "TS\r\n0\r\n>");
  EXPECT_EQ(run("TPSR"), "TPSR\r\n00000002\r\n>");

  set(0x6064, 0, 106019);
  EXPECT_EQ(run("TP"), "TP\r\n106019\r\n>");
  EXPECT_EQ(run("tp"), "TP\r\n106019\r\n>");
  EXPECT_EQ(run(" tp"), " TP\r\n106019\r\n>");
  set(0x6064, 0, -3658);
  EXPECT_EQ(run("TP"), "TP\r\n-3658\r\n>");
  EXPECT_EQ(run("OR6064,0"), "OR6064,0\r\nOR6064,0,-3658\r\n>");

  set(0x60FD, 0, (1 << 16) | (1 << 18));
  EXPECT_EQ(run("TI3"), "TI3\r\n1\r\n>");
  EXPECT_EQ(run("TI2"), "TI2\r\n0\r\n>");
  EXPECT_EQ(run("TI"), "TI\r\n0005\r\n>");
  EXPECT_EQ(run("OR60FD,0,h"), "OR60FD,0,H\r\nOR60FD,0,50000h\r\n>");
  set(0x60FD, 0, 1 << 17);
  EXPECT_EQ(run("OR 60FD,0"), "OR 60FD,0\r\nOR 60FD,0,131072\r\n>");
}

TEST_F(InterpreterTest, ParameterCommandsWriteTheirObjects) {
  EXPECT_EQ(run("SP720"), "SP720\r\n>");
  EXPECT_EQ(get(0x6081, 0), 720);
  EXPECT_EQ(run("AC5000"), "AC5000\r\n>");
  EXPECT_EQ(get(0x6083, 0), 5000);
  EXPECT_EQ(run("DE1000"), "DE1000\r\n>");
  EXPECT_EQ(get(0x6084, 0), 1000);
  EXPECT_EQ(run("PO10000"), "PO10000\r\n>");
  EXPECT_EQ(get(0x607A, 0), 10000);
  EXPECT_EQ(run("WA-100"), "WA-100\r\n>");
  EXPECT_EQ(get(0x607A, 0), -100);
  EXPECT_EQ(run("SP4294967295"), "SP4294967295\r\n>");
  EXPECT_EQ(get(0x6081, 0), 4294967295LL);
}

TEST_F(InterpreterTest, SpFollowsARunningJogOnlyInVelocityMode) {
  set(0x6061, 0, 3);
  set(0x60FF, 0, -500);
  EXPECT_EQ(run("SP800"), "SP800\r\n>");
  EXPECT_EQ(get(0x60FF, 0), -800);
  set(0x60FF, 0, 500);
  EXPECT_EQ(run("SP3000000000"), "SP3000000000\r\n>");
  EXPECT_EQ(get(0x60FF, 0), 2147483647);
  set(0x60FF, 0, 0);  // standing: SP must not start motion
  EXPECT_EQ(run("SP900"), "SP900\r\n>");
  EXPECT_EQ(get(0x60FF, 0), 0);
  set(0x6061, 0, 1);
  set(0x60FF, 0, 100);
  EXPECT_EQ(run("SP700"), "SP700\r\n>");
  EXPECT_EQ(get(0x60FF, 0), 100);
}

TEST_F(InterpreterTest, SoCoChangeOneOutputBit) {
  set(0x60FE, 1, 0);
  EXPECT_EQ(run("SO1"), "SO1\r\n>");
  EXPECT_EQ(get(0x60FE, 1), 1 << 16);
  EXPECT_EQ(run("SO4"), "SO4\r\n>");
  EXPECT_EQ(get(0x60FE, 1), (1 << 16) | (1 << 19));
  EXPECT_EQ(run("CO1"), "CO1\r\n>");
  EXPECT_EQ(get(0x60FE, 1), 1 << 19);
  EXPECT_EQ(run("co4"), "CO4\r\n>");
  EXPECT_EQ(get(0x60FE, 1), 0);
}

TEST_F(InterpreterTest, RwWtSetTheSharedVariables) {
  EXPECT_EQ(run("RW-2000"), "RW-2000\r\n>");
  EXPECT_EQ(in_.variables().repeat_way, -2000);
  EXPECT_EQ(run("WT5000"), "WT5000\r\n>");
  EXPECT_EQ(in_.variables().wait_time_ms, 5000U);
  in_.reset();
  EXPECT_EQ(in_.variables().repeat_way, 0);
  EXPECT_EQ(in_.variables().wait_time_ms, 0U);
}

TEST_F(InterpreterTest, FailedWriteChangesNothing) {
  set(0x6083, 0, 1234);
  EXPECT_EQ(run("AC-5"), "AC-5\r\nAC-5,ERROR,06090030h\r\n>");
  EXPECT_EQ(get(0x6083, 0), 1234);
}

TEST_F(InterpreterTest, StoreAnswersOnlyWhenDurable) {
  od::Done held;
  d_.release_store_hooks();  // this test's hook stands in for the persistence service
  od_.on_write(0x1010, 1, [&](od::WriteRequest& r) {
    if (std::get<std::int64_t>(r.value) != 0x65766173) return od::AbortCode::cannot_store;
    held = std::move(*r.done);
    return od::AbortCode::pending;
  });
  std::vector<std::string> late;
  auto r = in_.execute("OW1010,1,1702257011", [&](std::string s) { late.push_back(std::move(s)); });
  EXPECT_FALSE(r.has_value());
  EXPECT_TRUE(late.empty());
  ASSERT_TRUE(held);
  held(od::AbortCode::none);
  ASSERT_EQ(late.size(), 1U);
  EXPECT_EQ(late[0], "OW1010,1,1702257011\r\nOW1010,1,1702257011,OK\r\n>");

  r = in_.execute("ow1010,1,1702257011 ", [&](std::string s) { late.push_back(std::move(s)); });
  EXPECT_FALSE(r.has_value());
  held(od::AbortCode::hardware_error);
  ASSERT_EQ(late.size(), 2U);
  EXPECT_EQ(late[1], "OW1010,1,1702257011 \r\nOW1010,1,1702257011,ERROR,06060000h\r\n>");
}

// Every line, whatever its bytes, gets a reply that ends in the prompt (no crash, no exception).
TEST_F(InterpreterTest, GarbageAlwaysGetsAReply) {
  std::uint32_t seed = 12345;
  const std::string alphabet = "GWPOASMCQREFTIDVJNOR0123456789,-+hHxX \x80\xff";
  for (int i = 0; i < 20000; ++i) {
    std::string line;
    const int len = static_cast<int>(seed % 12);
    for (int k = 0; k < len; ++k) {
      seed = seed * 1103515245 + 12345;
      line.push_back(alphabet[(seed >> 16) % alphabet.size()]);
    }
    seed = seed * 1103515245 + 12345;
    // keep away from motion and store commands, which this dictionary-only test cannot serve
    const auto r = in_.execute(line);
    if (!r) continue;  // a random OW1010/1011 write: pending by design
    ASSERT_FALSE(r->empty());
    ASSERT_EQ(r->back(), '>') << line;
  }
}

}  // namespace
}  // namespace mcemu::refgo
