// The FAULHABER view of the core's faults (drive/faulhaber/fh_faults.hpp): error word 2320h, error
// register 1001h (class bit + bit 0) and the EMCY manufacturer bytes.
#include "drive/faulhaber/fh_faults.hpp"

#include <gtest/gtest.h>

#include "drive/faults.hpp"

namespace mcemu::core::faulhaber {
namespace {

std::uint32_t bit_of(FaultCause c) { return 1u << fault_info(c).bit; }

TEST(FhFaults, EveryCauseHasARowAndRaisedCausesHaveAnErrorBitAndBitZero) {
  for (const FaultInfo& f : fault_table()) {
    const FhFault& fh = fh_fault(f.cause);
    EXPECT_EQ(fh.cause, f.cause);
    if (f.kind == FaultKind::warning) continue;
    EXPECT_GE(fh.error_bit, 0) << to_string(f.cause);
    EXPECT_LE(fh.error_bit, 15);
    EXPECT_EQ(fh.reg & 0x01, 0x01) << to_string(f.cause);
    EXPECT_NE(fh.reg & 0xFE, 0) << "a class bit: " << to_string(f.cause);
    EXPECT_NE(fh.code, 0) << to_string(f.cause);
  }
}

TEST(FhFaults, SpecCodes) {
  // faulhaber.md §7.3 [fact: CANMAN Tab. 9–10]
  EXPECT_EQ(fh_fault(FaultCause::over_voltage).code, 0x3210);
  EXPECT_EQ(fh_fault(FaultCause::over_voltage).error_bit, 2);
  EXPECT_EQ(fh_fault(FaultCause::over_voltage).reg, 0x05);
  EXPECT_EQ(fh_fault(FaultCause::under_voltage).code, 0x3220);
  EXPECT_EQ(fh_fault(FaultCause::under_voltage).error_bit, 3);
  EXPECT_EQ(fh_fault(FaultCause::over_temperature).code, 0x4310);
  EXPECT_EQ(fh_fault(FaultCause::over_temperature).error_bit, 5);
  EXPECT_EQ(fh_fault(FaultCause::over_temperature).reg, 0x09);
  EXPECT_EQ(fh_fault(FaultCause::stroke).code, 0x8611);
  EXPECT_EQ(fh_fault(FaultCause::stroke).error_bit, 1);
  EXPECT_EQ(fh_fault(FaultCause::stroke).reg, 0x21);
  EXPECT_EQ(fh_fault(FaultCause::sensor).code, 0x7300);
  EXPECT_EQ(fh_fault(FaultCause::sensor).error_bit, 6);
  EXPECT_EQ(fh_fault(FaultCause::sensor).reg, 0x81);
}

TEST(FhFaults, WordAndRegisterCombineTheRaisedCauses) {
  EXPECT_EQ(error_word(0, false), 0);
  EXPECT_EQ(error_register(0, false), 0);
  EXPECT_EQ(error_word(0, true), 0x0010);
  EXPECT_EQ(error_register(0, true), 0x03);
  const std::uint32_t bits = bit_of(FaultCause::over_voltage) | bit_of(FaultCause::stroke);
  EXPECT_EQ(error_word(bits, false), 0x0006);
  EXPECT_EQ(error_register(bits, false), 0x25);
  EXPECT_EQ(error_word(bits | bit_of(FaultCause::sensor_warning), false), 0x0006) << "core warnings do not count";
  EXPECT_EQ(error_word(bit_of(FaultCause::over_temperature) | bit_of(FaultCause::i2t), true), 0x0030);
}

// Every code the table sends has a name; the web status and the footer show it (one table).
TEST(FhFaults, EveryCodeSentHasAName) {
  for (int c = 0; c < static_cast<int>(k_fault_cause_count); ++c) {
    const auto code = fh_fault(static_cast<FaultCause>(c)).code;
    if (code != 0) {
      EXPECT_NE(error_name(code), "unknown") << std::hex << code;
    }
  }
  EXPECT_EQ(error_name(0x8611), "following error");
  EXPECT_EQ(error_name(k_temperature_warning_code), "temperature warning");
  EXPECT_EQ(error_name(0x1234), "unknown");
}

TEST(FhFaults, EmcyDataIsTheErrorWordLittleEndianThenZeros) {
  EXPECT_EQ(emcy_data(0x0004), (std::array<std::uint8_t, 5>{0x04, 0x00, 0, 0, 0}));
  EXPECT_EQ(emcy_data(0x4102), (std::array<std::uint8_t, 5>{0x02, 0x41, 0, 0, 0}));
}

}  // namespace
}  // namespace mcemu::core::faulhaber
