// Frames of the FAULHABER MC V3.0 binary RS232 protocol (faulhaber.md §3, §5):
//   S(0x53) | L | node-id | command | data (L−4 bytes, numbers little-endian) | CRC-8 | E(0x45)
// L counts the bytes from L itself through the CRC (= data + 4), so a frame is L + 2 bytes long;
// L is 4 … 255. The builders below make the drive's messages of §5/§6. Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::faulhaber {

inline constexpr std::uint8_t k_sof = 0x53;  // 'S'
inline constexpr std::uint8_t k_eof = 0x45;  // 'E'
inline constexpr std::size_t k_min_length = 4;
inline constexpr std::size_t k_max_length = 255;
inline constexpr std::size_t k_max_data = k_max_length - 4;   // 251
inline constexpr std::size_t k_max_frame = k_max_length + 2;  // 257 bytes on the wire
inline constexpr std::size_t k_max_value = 58;                // expedited SDO value (COMM Tab. 2)
inline constexpr std::size_t k_error_frame_length = 11;       // L of a 0x03 error response

// Command codes of §5. 0x00 and 0x03 mean different things in the two directions.
namespace command {
inline constexpr std::uint8_t boot = 0x00;        // drive → host: boot message (device name)
inline constexpr std::uint8_t reset_node = 0x00;  // host → drive: device reset, no direct response
inline constexpr std::uint8_t sdo_read = 0x01;
inline constexpr std::uint8_t sdo_write = 0x02;
inline constexpr std::uint8_t sdo_error = 0x03;  // drive → host: error response (L = 11)
inline constexpr std::uint8_t sdo_abort = 0x03;  // host → drive: abort request, answered with L = 7
inline constexpr std::uint8_t controlword = 0x04;
inline constexpr std::uint8_t statusword = 0x05;  // drive → host notification
inline constexpr std::uint8_t logging = 0x06;     // not supported
inline constexpr std::uint8_t emcy = 0x07;        // drive → host notification
inline constexpr std::uint8_t block_read_init = 0x08;
inline constexpr std::uint8_t block_read_segment = 0x09;  // presumed (§5)
inline constexpr std::uint8_t block_read_end = 0x0A;
inline constexpr std::uint8_t block_write_init = 0x0B;
inline constexpr std::uint8_t block_write_download = 0x0C;
inline constexpr std::uint8_t block_write_end = 0x0D;
}  // namespace command

// A frame whose data lives elsewhere (a receiver's buffer): valid only as long as that buffer.
struct FrameView {
  std::uint8_t node = 0;
  std::uint8_t command = 0;
  std::span<const std::uint8_t> data;
};

struct Frame {
  std::uint8_t node = 0;
  std::uint8_t command = 0;
  std::vector<std::uint8_t> data;

  FrameView view() const { return {node, command, data}; }
  bool operator==(const Frame&) const = default;
};

// The wire bytes of a frame. Precondition: data ≤ k_max_data bytes (the drive never builds more;
// std::length_error otherwise — a programming error, not an input error).
std::vector<std::uint8_t> encode(FrameView f);
inline std::vector<std::uint8_t> encode(const Frame& f) { return encode(f.view()); }
// Appends the wire bytes to `out` (a session's output), without a temporary.
void append_encoded(std::string& out, FrameView f);

// One complete frame of exactly L + 2 bytes, checked like the receiver does (§4).
enum class DecodeError : std::uint8_t { none, too_short, no_sof, bad_length, bad_eof, bad_crc };
struct Decoded {
  DecodeError error = DecodeError::none;
  Frame frame;
};
Decoded decode(std::span<const std::uint8_t> bytes, bool check_crc = true);

// The drive's messages (node = the drive's node-id in use).
Frame sdo_read_response(std::uint8_t node, std::uint16_t index, std::uint8_t sub, std::span<const std::uint8_t> value);
Frame sdo_write_response(std::uint8_t node, std::uint16_t index, std::uint8_t sub);
Frame sdo_error_response(std::uint8_t node, std::uint16_t index, std::uint8_t sub, std::uint32_t abort_code);
Frame abort_acknowledge(std::uint8_t node, std::uint16_t index, std::uint8_t sub);  // L = 7
Frame controlword_response(std::uint8_t node, std::uint8_t error);                  // L = 5
Frame statusword_notification(std::uint8_t node, std::uint16_t statusword);         // L = 6
// 8 data bytes: code LE, error register (1001h), FAULHABER error word (2320h) LE, 3 × 0; L = 12.
Frame emcy_notification(std::uint8_t node, std::uint16_t code, std::uint8_t error_register, std::uint16_t error_word);
// The device name (1008h), ASCII, no terminator, at most k_max_value bytes (longer names are cut).
Frame boot_message(std::uint8_t node, std::string_view device_name);

// Little-endian helpers for the data bytes.
inline std::uint16_t le16(std::span<const std::uint8_t> d, std::size_t at) {
  return static_cast<std::uint16_t>(d[at] | (d[at + 1] << 8));
}
inline std::uint32_t le32(std::span<const std::uint8_t> d, std::size_t at) {
  return static_cast<std::uint32_t>(d[at]) | (static_cast<std::uint32_t>(d[at + 1]) << 8) |
         (static_cast<std::uint32_t>(d[at + 2]) << 16) | (static_cast<std::uint32_t>(d[at + 3]) << 24);
}

}  // namespace mcemu::faulhaber
