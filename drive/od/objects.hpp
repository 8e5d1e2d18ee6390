// Named indices of the objects that code outside their owner touches by number (the owner — the
// drive core, a protocol — keeps its own handles). One place for each number, so that a reader can
// find every user of an object and a second personality can tell which objects it must provide.
#pragma once

#include <cstdint>

namespace mcemu::od {

inline constexpr std::uint16_t k_error_register = 0x1001;
inline constexpr std::uint16_t k_device_name = 0x1008;
inline constexpr std::uint16_t k_software_version = 0x100A;
inline constexpr std::uint16_t k_store_parameters = 0x1010;
inline constexpr std::uint16_t k_restore_defaults = 0x1011;
inline constexpr std::uint16_t k_identity = 0x1018;
inline constexpr std::uint16_t k_program_control = 0x1F51;  // CiA 302: program control of the script
inline constexpr std::uint16_t k_script = 0x3500;           // MovingCap CODE script record (scripting.md §3)
inline constexpr std::uint16_t k_device_info = 0x3404;      // MovingCap identity extras (.04 serial)
inline constexpr std::uint16_t k_ip_address = 0x5007;       // active IP address, .01–.04 octets
inline constexpr std::uint16_t k_ip_mask = 0x5008;          // subnet mask, .01–.04 octets
inline constexpr std::uint16_t k_error_code = 0x603F;
inline constexpr std::uint16_t k_controlword = 0x6040;
inline constexpr std::uint16_t k_statusword = 0x6041;

// 3500h sub-indices (scripting.md §3.1).
inline constexpr std::uint8_t k_script_id = 0x01;
inline constexpr std::uint8_t k_script_state = 0x02;
inline constexpr std::uint8_t k_script_line = 0x03;
inline constexpr std::uint8_t k_script_autostart = 0x04;
inline constexpr std::uint8_t k_script_length = 0x05;
inline constexpr std::uint8_t k_script_crc32 = 0x06;

}  // namespace mcemu::od
