#include "protocols/faulhaber/frame.hpp"

#include <algorithm>
#include <stdexcept>

#include "protocols/faulhaber/crc.hpp"

namespace mcemu::faulhaber {

namespace {

void put16(std::vector<std::uint8_t>& d, std::uint16_t v) {
  d.push_back(static_cast<std::uint8_t>(v));
  d.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put32(std::vector<std::uint8_t>& d, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) d.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::vector<std::uint8_t> address(std::uint16_t index, std::uint8_t sub, std::size_t extra = 0) {
  std::vector<std::uint8_t> d;
  d.reserve(3 + extra);
  put16(d, index);
  d.push_back(sub);
  return d;
}

void check_size(FrameView f) {
  if (f.data.size() > k_max_data) throw std::length_error("faulhaber frame: more than 251 data bytes");
}

}  // namespace

std::vector<std::uint8_t> encode(FrameView f) {
  check_size(f);
  std::vector<std::uint8_t> out;
  out.reserve(f.data.size() + 6);
  out.push_back(k_sof);
  out.push_back(static_cast<std::uint8_t>(f.data.size() + 4));
  out.push_back(f.node);
  out.push_back(f.command);
  out.insert(out.end(), f.data.begin(), f.data.end());
  out.push_back(crc8(std::span<const std::uint8_t>(out).subspan(1)));
  out.push_back(k_eof);
  return out;
}

void append_encoded(std::string& out, FrameView f) {
  check_size(f);
  const std::uint8_t head[3] = {static_cast<std::uint8_t>(f.data.size() + 4), f.node, f.command};
  const std::uint8_t crc = crc8_update(crc8(head), f.data);
  out.reserve(out.size() + f.data.size() + 6);
  out.push_back(static_cast<char>(k_sof));
  for (const auto b : head) out.push_back(static_cast<char>(b));
  for (const auto b : f.data) out.push_back(static_cast<char>(b));
  out.push_back(static_cast<char>(crc));
  out.push_back(static_cast<char>(k_eof));
}

Decoded decode(std::span<const std::uint8_t> bytes, bool check_crc) {
  Decoded d;
  if (bytes.size() < k_min_length + 2) {
    d.error = DecodeError::too_short;
  } else if (bytes[0] != k_sof) {
    d.error = DecodeError::no_sof;
  } else if (bytes[1] < k_min_length || bytes.size() != static_cast<std::size_t>(bytes[1]) + 2) {
    d.error = DecodeError::bad_length;
  } else if (bytes.back() != k_eof) {
    d.error = DecodeError::bad_eof;
  } else if (check_crc && crc8(bytes.subspan(1, bytes[1] - 1)) != bytes[bytes[1]]) {
    d.error = DecodeError::bad_crc;
  } else {
    d.frame.node = bytes[2];
    d.frame.command = bytes[3];
    d.frame.data.assign(bytes.begin() + 4, bytes.begin() + bytes[1]);
  }
  return d;
}

Frame sdo_read_response(std::uint8_t node, std::uint16_t index, std::uint8_t sub, std::span<const std::uint8_t> value) {
  Frame f{node, command::sdo_read, address(index, sub, value.size())};
  f.data.insert(f.data.end(), value.begin(), value.end());
  return f;
}

Frame sdo_write_response(std::uint8_t node, std::uint16_t index, std::uint8_t sub) {
  return {node, command::sdo_write, address(index, sub)};
}

Frame sdo_error_response(std::uint8_t node, std::uint16_t index, std::uint8_t sub, std::uint32_t abort_code) {
  Frame f{node, command::sdo_error, address(index, sub, 4)};
  put32(f.data, abort_code);
  return f;
}

Frame abort_acknowledge(std::uint8_t node, std::uint16_t index, std::uint8_t sub) {
  return {node, command::sdo_abort, address(index, sub)};
}

Frame controlword_response(std::uint8_t node, std::uint8_t error) { return {node, command::controlword, {error}}; }

Frame statusword_notification(std::uint8_t node, std::uint16_t statusword) {
  Frame f{node, command::statusword, {}};
  put16(f.data, statusword);
  return f;
}

Frame emcy_notification(std::uint8_t node, std::uint16_t code, std::uint8_t error_register, std::uint16_t error_word) {
  Frame f{node, command::emcy, {}};
  f.data.reserve(8);
  put16(f.data, code);
  f.data.push_back(error_register);
  put16(f.data, error_word);
  f.data.insert(f.data.end(), 3, 0);
  return f;
}

Frame boot_message(std::uint8_t node, std::string_view device_name) {
  const std::size_t n = std::min(device_name.size(), k_max_value);
  Frame f{node, command::boot, {}};
  f.data.assign(device_name.begin(), device_name.begin() + static_cast<std::ptrdiff_t>(n));
  return f;
}

}  // namespace mcemu::faulhaber
