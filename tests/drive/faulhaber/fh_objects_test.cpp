// The pure rules behind 2311h and 2324h.01 (drive/faulhaber/fh_objects.hpp).
#include "drive/faulhaber/fh_objects.hpp"

#include <gtest/gtest.h>

namespace mcemu::core::faulhaber {
namespace {

struct InputCase {
  std::uint16_t physical;
  InputConfig config;
  std::uint16_t logical;
  bool negative;
  bool positive;
};

class Inputs : public ::testing::TestWithParam<InputCase> {};

TEST_P(Inputs, LogicalStateAndLimitSwitches) {
  const auto& c = GetParam();
  const InputState s = evaluate_inputs(c.physical, 0x00FF, c.config);
  EXPECT_EQ(s.physical, c.physical & 0xFF);
  EXPECT_EQ(s.logical, c.logical);
  EXPECT_EQ(s.limit_negative, c.negative);
  EXPECT_EQ(s.limit_positive, c.positive);
}

INSTANTIATE_TEST_SUITE_P(
    Table, Inputs,
    ::testing::Values(InputCase{0x00, {0, 0, 0}, 0x00, false, false}, InputCase{0x04, {4, 0, 0}, 0x04, true, false},
                      InputCase{0x04, {0, 4, 0}, 0x04, false, true}, InputCase{0x00, {4, 0, 4}, 0x04, true, false},
                      InputCase{0x04, {4, 0, 4}, 0x00, false, false}, InputCase{0x0C, {4, 8, 0}, 0x0C, true, true},
                      InputCase{0x81, {0x80, 0x01, 0}, 0x81, true, true},
                      InputCase{
                          0x100, {0, 0, 0xFF00}, 0x00, false, false},  // no DigIn9; polarity of absent pins ignored
                      InputCase{0x00, {0, 0, 0xFFFF}, 0xFF, false, false}));

TEST(Inputs, OnlyExistingPinsCount) {
  const InputState s = evaluate_inputs(0xFF, 0x07, InputConfig{0x08, 0x04, 0});
  EXPECT_EQ(s.physical, 0x07);
  EXPECT_EQ(s.logical, 0x07);
  EXPECT_FALSE(s.limit_negative) << "DigIn4 does not exist";
  EXPECT_TRUE(s.limit_positive);
}

struct OutputCase {
  std::uint16_t state;
  std::uint16_t command;
  std::uint16_t outputs;
  std::uint16_t expected;
};

class Outputs : public ::testing::TestWithParam<OutputCase> {};

TEST_P(Outputs, TwoBitsPerOutput) {
  const auto& c = GetParam();
  EXPECT_EQ(apply_output_command(c.state, c.command, c.outputs), c.expected) << std::hex << c.state << " " << c.command;
}

INSTANTIATE_TEST_SUITE_P(Table, Outputs,
                         ::testing::Values(OutputCase{0b00, 0x00FD, 0b11, 0b01},  // DigOut1 on
                                           OutputCase{0b01, 0x00FC, 0b11, 0b00},  // DigOut1 off
                                           OutputCase{0b00, 0x00FE, 0b11, 0b01},  // toggle
                                           OutputCase{0b01, 0x00FE, 0b11, 0b00},  // toggle
                                           OutputCase{0b01, 0x00F7, 0b11, 0b11},  // DigOut2 on
                                           OutputCase{0b11, 0x00F3, 0b11, 0b01},  // DigOut2 off
                                           OutputCase{0b10, 0xFFFF, 0b11, 0b10},  // unchanged
                                           OutputCase{0b00, 0x0015, 0b11, 0b11},  // DigOut3 does not exist
                                           OutputCase{0b00, 0x0015, 0b111, 0b111},
                                           OutputCase{0b11, 0x0000, 0b11, 0b00}));

TEST(DeviceStatus, BitPositions) {
  const auto only = [](auto set) {
    DeviceStatus s;
    set(s);
    return device_status_word(s);
  };
  EXPECT_EQ(device_status_word({}), 0u);
  EXPECT_EQ(only([](DeviceStatus& s) { s.following_error = true; }), 1u << 5);
  EXPECT_EQ(only([](DeviceStatus& s) { s.limit_positive = true; }), 1u << 6);
  EXPECT_EQ(only([](DeviceStatus& s) { s.limit_negative = true; }), 1u << 7);
  EXPECT_EQ(only([](DeviceStatus& s) { s.soft_limit_positive = true; }), 1u << 8);
  EXPECT_EQ(only([](DeviceStatus& s) { s.soft_limit_negative = true; }), 1u << 9);
  EXPECT_EQ(only([](DeviceStatus& s) { s.torque_limited = true; }), 1u << 14);
  EXPECT_EQ(only([](DeviceStatus& s) { s.temperature_warning = true; }), 1u << 16);
  EXPECT_EQ(only([](DeviceStatus& s) { s.temperature_error = true; }), 1u << 17);
  EXPECT_EQ(only([](DeviceStatus& s) { s.over_voltage = true; }), 1u << 18);
  EXPECT_EQ(only([](DeviceStatus& s) { s.under_voltage = true; }), 1u << 19);
}

}  // namespace
}  // namespace mcemu::core::faulhaber
