// CiA 402 decoding and the drive view (lint/drive_view.cpp).
#include "lint/drive_view.hpp"

#include <gtest/gtest.h>

namespace mcemu::lint {
namespace {

TEST(PdsOf, StatuswordsOfDriveCore) {
  // drive-core.md §4.1 and §5 (values a client sees), faulhaber.md §7.1
  const std::pair<std::uint16_t, Pds> cases[] = {{0x0000, Pds::not_ready_to_switch_on},
                                                 {0x0040, Pds::switch_on_disabled},
                                                 {0x0021, Pds::ready_to_switch_on},
                                                 {0x0023, Pds::switched_on},
                                                 {0x0027, Pds::operation_enabled},
                                                 {0x1127, Pds::operation_enabled},
                                                 {0x0427, Pds::operation_enabled},
                                                 {0x0107, Pds::quick_stop_active},
                                                 {0x0407, Pds::quick_stop_active},
                                                 {0x010F, Pds::fault_reaction_active},
                                                 {0x000F, Pds::fault_reaction_active},
                                                 {0x0008, Pds::fault},
                                                 {0x0088, Pds::fault},
                                                 {0x00C0, Pds::switch_on_disabled}};
  for (const auto& [sw, state] : cases) EXPECT_EQ(pds_of(sw), state) << std::hex << sw;
}

TEST(CommandOf, MasksOfDriveCore) {
  // drive-core.md §4.2
  EXPECT_EQ(command_of(0x0006), Command::shutdown);
  EXPECT_EQ(command_of(0x000E), Command::shutdown);
  EXPECT_EQ(command_of(0x0007), Command::switch_on);
  EXPECT_EQ(command_of(0x000F), Command::enable_operation);
  EXPECT_EQ(command_of(0x003F), Command::enable_operation);
  EXPECT_EQ(command_of(0x0000), Command::disable_voltage);
  EXPECT_EQ(command_of(0x000D), Command::disable_voltage);
  EXPECT_EQ(command_of(0x0002), Command::quick_stop);
  EXPECT_EQ(command_of(0x000B), Command::quick_stop);
}

TEST(TargetOf, QuickStopDependsOnTheState) {
  EXPECT_EQ(target_of(Command::quick_stop, Pds::operation_enabled), Pds::quick_stop_active);
  EXPECT_EQ(target_of(Command::quick_stop, Pds::quick_stop_active), Pds::quick_stop_active);
  EXPECT_EQ(target_of(Command::quick_stop, Pds::switched_on), Pds::switch_on_disabled);
  EXPECT_EQ(target_of(Command::switch_on, Pds::operation_enabled), Pds::switched_on);
}

TEST(DriveView, AppliesAcceptedWritesOnly) {
  DriveView v;
  OdWrite w;
  w.index = 0x6040;
  w.value = 0x001F;
  w.statusword_after = 0x1127;
  w.mode_after = 1;
  v.apply(w);
  EXPECT_EQ(v.controlword, 0x001F);
  EXPECT_EQ(v.statusword, 0x1127);
  EXPECT_TRUE(v.moving());
  w.index = 0x607A;
  v.apply(w);
  EXPECT_TRUE(v.target_changed);
  w.index = 0x6060;
  w.value = 3;
  w.result = od::AbortCode::invalid_value;
  w.statusword_after = 0x0027;
  v.apply(w);
  EXPECT_EQ(v.mode_command, 0);     // refused
  EXPECT_EQ(v.statusword, 0x0027);  // the sample is current anyway
  w.index = 0x6040;
  w.value = 0x000F;
  w.result = od::AbortCode::none;
  v.apply(w);
  w.value = 0x001F;
  v.apply(w);
  EXPECT_FALSE(v.target_changed);  // a rising edge of bit 4 takes the target
}

TEST(DriveView, CoreEvents) {
  DriveView v;
  const core::Event a = core::StatuswordChanged{0x0040, 0x0021};
  v.apply(CoreEvent{1, a});
  EXPECT_EQ(v.state(), Pds::ready_to_switch_on);
  const core::Event b = core::ModeDisplayChanged{6};
  v.apply(CoreEvent{1, b});
  EXPECT_EQ(v.mode_display, 6);
  const core::Event c = core::PowerStage{true};
  v.apply(CoreEvent{1, c});
  EXPECT_EQ(v.statusword, 0x0021);
}

}  // namespace
}  // namespace mcemu::lint
