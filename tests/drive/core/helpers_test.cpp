// The helper commands of drive-core.md §12 (EnableDrive, PowerQuit, Go…, AUTOENABLE, Chk…).
#include "drive/helpers/helpers.hpp"

#include <gtest/gtest.h>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;
namespace h = helpers;

struct Fixture {
  Drive d;
  h::DriveRef ref{d.core, d.od, od::Origin::script};
  explicit Fixture(const std::string& model = "MC349") : d(model) { d.step(); }
};

TEST(Helpers, EnableDriveFromEveryState) {
  Fixture f;
  EXPECT_TRUE(h::enable_drive(f.ref));
  EXPECT_TRUE(h::chk_enabled(f.ref));
  f.d.cw(0x06);
  EXPECT_TRUE(h::enable_drive(f.ref));
  f.d.set(0x605A, 0, 5);
  f.d.cw(0x02);
  f.d.step(5);
  EXPECT_TRUE(h::enable_drive(f.ref)) << "from QSA by transition 16";
  f.d.core.inject(FaultCause::sensor);
  f.d.step();
  EXPECT_FALSE(h::enable_drive(f.ref)) << "cause still present";
  EXPECT_EQ(f.d.core.state(), PdsState::fault);
  f.d.core.clear(FaultCause::sensor);
  EXPECT_TRUE(h::enable_drive(f.ref)) << "fresh bit-7 edge: 0x0000 then 0x0080";
}

TEST(Helpers, PowerQuitResetsFaultAndDisables) {
  Fixture f;
  h::enable_drive(f.ref);
  h::power_quit(f.ref);
  EXPECT_EQ(f.d.core.state(), PdsState::switch_on_disabled);
  EXPECT_EQ(f.d.read(0x6060), 0);
  f.d.core.inject(FaultCause::stroke);
  ASSERT_EQ(f.d.core.state(), PdsState::fault);
  h::power_quit(f.ref);
  EXPECT_EQ(f.d.core.state(), PdsState::switch_on_disabled);
  f.d.core.inject(FaultCause::needs_reset);
  f.d.step();
  h::power_quit(f.ref);
  EXPECT_EQ(f.d.core.state(), PdsState::fault) << "refused while the cause is present";
}

TEST(Helpers, GoPosAbsAutoEnablesAndMoves) {
  Fixture f;
  EXPECT_EQ(h::go_pos_abs(f.ref, 50000), od::AbortCode::none);
  EXPECT_EQ(f.d.core.state(), PdsState::operation_enabled);
  EXPECT_EQ(f.d.read(0x6061), 1) << "mode switch applied at once";
  EXPECT_EQ(f.d.read(0x6040), 0x3F);
  f.d.step_until([&] { return h::chk_ready(f.ref); }, 2000);
  EXPECT_EQ(h::get_actual_pos(f.ref), 50000);
  EXPECT_EQ(h::go_pos_rel(f.ref, -20000), od::AbortCode::none);
  EXPECT_TRUE(h::chk_moving(f.ref) || !h::chk_ready(f.ref));
  f.d.step(1000);
  EXPECT_EQ(h::get_actual_pos(f.ref), 30000);
}

TEST(Helpers, AutoEnableStopsWhenSwitchOnFaults) {
  Fixture f;
  f.d.set(0x3511, 1, 0x0900);  // software enable on IN1, which is low
  EXPECT_EQ(h::go_pos_abs(f.ref, 50000), od::AbortCode::device_state);
  EXPECT_EQ(f.d.core.state(), PdsState::fault);
  EXPECT_TRUE(h::chk_error(f.ref));
  EXPECT_TRUE(h::chk_mfr_status(f.ref, 9));
  EXPECT_EQ(h::go_pos_abs(f.ref, 50000), od::AbortCode::device_state) << "no automatic fault reset";
  EXPECT_EQ(h::go_pos_rel(f.ref, 1234), od::AbortCode::device_state);
  EXPECT_EQ(f.d.od.number(0x607A, 0), 1234) << "the target is written although no motion starts (§12)";
  EXPECT_FALSE(h::chk_moving(f.ref));
}

TEST(Helpers, GoVelClearsHaltAndIsRefusedOnRabbit) {
  Fixture f;
  h::enable_drive(f.ref);
  f.d.cw(0x10F);
  EXPECT_EQ(h::go_vel(f.ref, 300), od::AbortCode::none);
  EXPECT_EQ(f.d.read(0x6040), 0x0F);
  f.d.step(400);
  EXPECT_EQ(f.d.read(0x606B), 300);
  Fixture r("MCFLAT");
  EXPECT_EQ(h::go_vel(r.ref, 300), od::AbortCode::invalid_value);
  EXPECT_EQ(r.d.core.state(), PdsState::switch_on_disabled) << "the helper ends before AUTOENABLE";
}

// drive-core.md §12: GoHome ends at the first refused write and names it (entry, value, abort
// code), so its callers can say which write it was; the writes after it are not made.
TEST(Helpers, GoHomeNamesTheRefusedWrite) {
  Fixture f;
  const std::int64_t offset = f.d.read(0x607C);
  auto r = h::go_home(f.ref, 35, 500, 0, 1234);  // 609Ah := 0 is below its minimum 1
  EXPECT_EQ(r, od::AbortCode::value_too_low);
  ASSERT_TRUE(r.refused);
  EXPECT_EQ(r.refused->index, 0x609A);
  EXPECT_EQ(r.refused->sub, 0);
  EXPECT_EQ(r.refused->value, 0);
  EXPECT_EQ(h::describe(r), "609Ah.00h := 0 refused, 06090032h");
  EXPECT_EQ(f.d.read(0x6099, 1), 500) << "the writes before it were made";
  EXPECT_EQ(f.d.read(0x607C), offset) << "the writes after it were not";
  EXPECT_NE(f.d.read(0x6060), 6) << "no mode switch";

  r = h::go_home(f.ref, -19, 500, 1000, 0);  // every write accepted, AUTOENABLE reaches OE
  EXPECT_TRUE(r.ok());
  EXPECT_FALSE(r.refused);
  EXPECT_EQ(h::describe(r), "ok");

  f.d.core.inject(FaultCause::sensor);
  f.d.step();
  r = h::go_home(f.ref, -19, 500, 1000, 0);  // no write refused: AUTOENABLE cannot leave Fault
  EXPECT_EQ(r, od::AbortCode::device_state);
  EXPECT_FALSE(r.refused);
  EXPECT_EQ(h::describe(r), "Operation enabled not reached, 08000022h");
}

TEST(Helpers, ObjectAccessAndChecks) {
  Fixture f;
  EXPECT_EQ(h::write_object(f.ref, 0x6081, 0, 1234), 0);
  EXPECT_EQ(h::read_object(f.ref, 0x6081, 0), 1234);
  EXPECT_EQ(static_cast<std::uint32_t>(h::write_object(f.ref, 0x6041, 0, 1)), 0x06010002u);
  EXPECT_EQ(static_cast<std::uint32_t>(h::read_object(f.ref, 0x7777, 0)), 0x06020000u);
  EXPECT_EQ(h::write_object(f.ref, 0x6092, 1, 0xFFFFFFFF), 0);
  EXPECT_EQ(h::read_object(f.ref, 0x6092, 1), -1) << "u32 reinterpreted";
  EXPECT_EQ(h::set_acc(f.ref, 2000), od::AbortCode::none);
  EXPECT_EQ(h::set_dec(f.ref, 3000), od::AbortCode::none);
  EXPECT_EQ(h::set_torque(f.ref, 500), od::AbortCode::none);
  EXPECT_EQ(h::set_op_mode(f.ref, 3), od::AbortCode::none);
  EXPECT_EQ(h::get_op_mode(f.ref), 3);
  EXPECT_EQ(f.d.read(0x6083), 2000);
  EXPECT_EQ(f.d.read(0x6084), 3000);
  EXPECT_EQ(f.d.read(0x6073), 500);
  EXPECT_FALSE(h::chk_enabled(f.ref));
  EXPECT_FALSE(h::chk_ready(f.ref));
  EXPECT_EQ(h::read_statusword(f.ref), 0x0040);
}

TEST(Helpers, StopAndContinueMotion) {
  Fixture f;
  h::go_vel(f.ref, 1000);
  f.d.step(700);
  h::stop_motion(f.ref);
  EXPECT_EQ(f.d.core.state(), PdsState::quick_stop_active);
  f.d.step(700);
  EXPECT_EQ(f.d.read(0x606B), 0);
  h::continue_motion(f.ref);
  EXPECT_EQ(f.d.core.state(), PdsState::operation_enabled);
  f.d.step(700);
  EXPECT_EQ(f.d.read(0x606B), 1000) << "PV tracks 60FFh again";
}

TEST(Helpers, ScriptEmcyChangesNothing) {
  Fixture f;
  h::send_emcy_msg(f.ref, 3);
  f.d.collect();
  const auto e = f.d.of<Emcy>();
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].bytes(), (std::array<std::uint8_t, 8>{0x9B, 0x50, 0x00, 0x03, 0, 0, 0, 0}));
  EXPECT_EQ(f.d.read(0x1001), 0);
  EXPECT_EQ(f.d.read(0x603F), 0);
  EXPECT_EQ(f.d.read(0x1003, 0), 0);
  EXPECT_EQ(f.d.core.state(), PdsState::switch_on_disabled);
}

TEST(Helpers, StoreAndFactoryResetAreOdWrites) {
  Fixture f;
  f.d.release_store_hooks();  // the bundle's persistence service stands aside for this test's hook
  od::Done taken;
  f.d.od.on_write(0x1010, 1, [&](od::WriteRequest& req) {
    EXPECT_EQ(std::get<std::int64_t>(req.value), 0x65766173);
    taken = std::move(*req.done);
    return od::AbortCode::pending;
  });
  int completions = 0;
  EXPECT_EQ(h::store_permanent(f.ref, [&](od::AbortCode c) { completions += c == od::AbortCode::none; }),
            od::AbortCode::pending);
  ASSERT_TRUE(taken);
  taken(od::AbortCode::none);
  EXPECT_EQ(completions, 1) << "the caller's completion is passed on";
  EXPECT_EQ(h::reset_to_factory(f.ref), od::AbortCode::none);
  EXPECT_EQ(f.d.read(0x1011, 1), 0x64616F6C);
}

}  // namespace
}  // namespace mcemu::core
