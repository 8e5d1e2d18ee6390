// The drive-side helper commands of drive-core.md §12 (mcdrive names in comments), shared by
// RefGo, the web API, MovingCap CODE scripts and the I/O functions.
//
// Contract: every helper is a sequence of ordinary OD writes with the caller's origin (full
// validation and hooks, exactly what a master doing the same writes gets), plus the few core
// calls §12 names (apply_mode_switch_now, resume_interrupted_motion, set_home_here). All writes of
// one helper happen inside the call, before the next simulation step (§2.5). Single-threaded, on
// the event-loop thread. Motion helpers return AbortCode::none, the abort code of the first
// refused write, or AbortCode::device_state when AUTOENABLE could not reach Operation enabled
// (§12: the helper then starts no motion). The writes of a multi-write helper (enable, power quit,
// stop, continue, AUTOENABLE, the Go helpers) carry ObjectDictionary::HelperScope for the write
// tap: the master lint judges the master's decisions, not the drive's own sequences.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::core::helpers {

// The drive a helper acts on and who is asking.
struct DriveRef {
  DriveCore& core;
  od::ObjectDictionary& od;
  od::Origin origin;
};

// WriteObject(i, s, v): 0 or the SDO abort code as int32.
std::int32_t write_object(const DriveRef& d, std::uint16_t index, std::uint8_t sub, std::int64_t value);
// ReadObject(i, s): value as int32 (u32 reinterpreted), or the abort code as int32.
std::int32_t read_object(const DriveRef& d, std::uint16_t index, std::uint8_t sub);
void write_control(const DriveRef& d, std::uint16_t cw);  // WriteControl
std::uint16_t read_statusword(const DriveRef& d);         // ReadStatusword

bool enable_drive(const DriveRef& d);     // EnableDrive: true when OE
void power_quit(const DriveRef& d);       // PowerQuit
void stop_motion(const DriveRef& d);      // StopMotion (605Ah := 6, quick stop)
void continue_motion(const DriveRef& d);  // ContinueMotion (transition 16 + resume)
// AUTOENABLE (refgo.md §7.1): the writes needed to reach OE from SOD/RTSO/SO/QSA; false if not OE.
bool autoenable(const DriveRef& d);

od::AbortCode go_pos_abs(const DriveRef& d, std::int32_t position);  // GoPosAbs
od::AbortCode go_pos_rel(const DriveRef& d, std::int32_t distance);  // GoPosRel
od::AbortCode go_vel(const DriveRef& d, std::int32_t velocity);      // GoVel
// What a helper that writes several entries did, naming the write the dictionary refused — its
// caller reports which one (drive-core.md §12) instead of an abort code alone. Compares equal to
// its AbortCode.
struct HelperResult {
  struct Write {
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    std::int64_t value = 0;
  };
  od::AbortCode code = od::AbortCode::none;  // none, the refused write's code, or device_state
  std::optional<Write> refused;              // the write that was refused (code is its abort code)
  bool ok() const { return code == od::AbortCode::none; }
  friend bool operator==(const HelperResult& r, od::AbortCode c) { return r.code == c; }
};
// "ok", "609Ah.00h := 0 refused, 06090032h", "Operation enabled not reached, 08000022h".
std::string describe(const HelperResult& r);

// GoHome(method, 6099h.01, 609Ah, 607Ch): the first refused write ends it and is named.
HelperResult go_home(const DriveRef& d, std::int8_t method, std::uint32_t speed, std::uint32_t acceleration,
                     std::int32_t offset);

od::AbortCode set_target_pos(const DriveRef& d, std::int32_t v);  // 607Ah
od::AbortCode set_pos_vel(const DriveRef& d, std::uint32_t v);    // 6081h
od::AbortCode set_acc(const DriveRef& d, std::uint32_t v);        // 6083h
od::AbortCode set_dec(const DriveRef& d, std::uint32_t v);        // 6084h
od::AbortCode set_op_mode(const DriveRef& d, std::int8_t v);      // 6060h
od::AbortCode set_torque(const DriveRef& d, std::uint16_t v);     // 6073h
std::int8_t get_op_mode(const DriveRef& d);                       // 6060h
std::int32_t get_actual_pos(const DriveRef& d);                   // 6064h

bool chk_ready(const DriveRef& d);                // 6041h bit 10 or bit 3
bool chk_enabled(const DriveRef& d);              // (6041h & 0x6F) == 0x27
bool chk_moving(const DriveRef& d);               // 6041h bit 8
bool chk_error(const DriveRef& d);                // 6041h bit 3
bool chk_mfr_status(const DriveRef& d, int bit);  // bit of 1002h

// SendEmcyMsg(errorNumber, errorRegister = 0, errorCode = 0x509B), §11.8.
void send_emcy_msg(const DriveRef& d, std::uint32_t error_number, std::uint8_t error_register = 0,
                   std::uint16_t error_code = 0x509B);

// 1010h.01 := "save" / 1011h.01 := "load"; may answer pending and complete through done
// (persistence.md). Storage itself is not the core's business.
od::AbortCode store_permanent(const DriveRef& d, od::Done done = {});
od::AbortCode reset_to_factory(const DriveRef& d, od::Done done = {});

}  // namespace mcemu::core::helpers
