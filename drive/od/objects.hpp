// Named indices of the objects that code outside their owner touches by number (the owner — the
// drive core, a protocol — keeps its own handles). One place for each number, so that a reader can
// find every user of an object and a second personality can tell which objects it must provide.
#pragma once

#include <cstdint>

namespace mcemu::od {

inline constexpr std::uint16_t k_error_register = 0x1001;
inline constexpr std::uint16_t k_mfr_status = 0x1002;     // manufacturer status register (fault bits)
inline constexpr std::uint16_t k_error_history = 0x1003;  // pre-defined error field: .00 count, .01 newest
inline constexpr std::uint16_t k_device_name = 0x1008;
inline constexpr std::uint16_t k_software_version = 0x100A;
inline constexpr std::uint16_t k_store_parameters = 0x1010;
inline constexpr std::uint16_t k_restore_defaults = 0x1011;
inline constexpr std::uint16_t k_identity = 0x1018;
inline constexpr std::uint16_t k_program_control = 0x1F51;  // CiA 302: program control of the script
inline constexpr std::uint16_t k_gateway = 0x3401;          // MovingCap gateway values (.0A temperature °C)
inline constexpr std::uint16_t k_device_info = 0x3404;      // MovingCap identity extras (.04 serial)
inline constexpr std::uint16_t k_script = 0x3500;           // MovingCap CODE script record (scripting.md §3)
inline constexpr std::uint16_t k_io_simulation = 0x3510;    // .01 virtual inputs, .02 I/O command (iofunc.md)
inline constexpr std::uint16_t k_ip_address = 0x5007;       // active IP address, .01–.04 octets
inline constexpr std::uint16_t k_ip_mask = 0x5008;          // subnet mask, .01–.04 octets
inline constexpr std::uint16_t k_error_code = 0x603F;
inline constexpr std::uint16_t k_controlword = 0x6040;
inline constexpr std::uint16_t k_statusword = 0x6041;
inline constexpr std::uint16_t k_mode = 0x6060;          // modes of operation
inline constexpr std::uint16_t k_mode_display = 0x6061;  // modes of operation display
inline constexpr std::uint16_t k_position_inc = 0x6063;  // position actual value, increments
inline constexpr std::uint16_t k_position = 0x6064;      // position actual value, user units
inline constexpr std::uint16_t k_velocity = 0x606C;      // velocity actual value, user units
inline constexpr std::uint16_t k_current = 0x6078;       // current actual value
inline constexpr std::uint16_t k_target_position = 0x607A;
inline constexpr std::uint16_t k_polarity = 0x607E;
inline constexpr std::uint16_t k_encoder_resolution = 0x608F;  // .01 increments per .02 motor revolutions
inline constexpr std::uint16_t k_digital_inputs = 0x60FD;
inline constexpr std::uint16_t k_digital_outputs = 0x60FE;  // .01 the output word

// Sub-indices of the objects above that other components name.
inline constexpr std::uint8_t k_gateway_temperature = 0x0A;  // 3401h.0A
inline constexpr std::uint8_t k_device_info_serial = 0x04;   // 3404h.04
inline constexpr std::uint8_t k_virtual_inputs = 0x01;       // 3510h.01

// The signatures that 1010h/1011h .01–.03 accept (CiA 301): "save" and "load" in ASCII.
inline constexpr std::int64_t k_save_signature = 0x65766173;
inline constexpr std::int64_t k_load_signature = 0x64616F6C;

// 3500h sub-indices (scripting.md §3.1).
inline constexpr std::uint8_t k_script_id = 0x01;
inline constexpr std::uint8_t k_script_state = 0x02;
inline constexpr std::uint8_t k_script_line = 0x03;
inline constexpr std::uint8_t k_script_autostart = 0x04;
inline constexpr std::uint8_t k_script_length = 0x05;
inline constexpr std::uint8_t k_script_crc32 = 0x06;

}  // namespace mcemu::od
