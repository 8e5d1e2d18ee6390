#include "protocols/faulhaber/describe.hpp"

namespace mcemu::faulhaber {

// Text is built by appending characters: operator+ chains and short-string assignments followed
// by appends make GCC 12 report a false -Wrestrict (see tests/fuzz/refgo_session.cpp).
void append_hex(std::string& s, std::uint32_t v, int digits) {
  static constexpr char k_digits[] = "0123456789ABCDEF";
  for (int i = digits - 1; i >= 0; --i) s.push_back(k_digits[(v >> (4 * i)) & 0xF]);
}

namespace {

// "6041.00"
void address(std::string& s, std::span<const std::uint8_t> d) {
  append_hex(s, le16(d, 0), 4);
  s.push_back('.');
  append_hex(s, d[2], 2);
}

// A value as the client sees it: 1, 2 or 4 bytes as a number, other lengths as text or hex.
void value(std::string& s, std::span<const std::uint8_t> v) {
  if (v.size() == 1 || v.size() == 2 || v.size() == 4) {
    std::uint32_t n = 0;
    for (std::size_t i = 0; i < v.size(); ++i) n |= static_cast<std::uint32_t>(v[i]) << (8 * i);
    s.append("0x");
    append_hex(s, n, static_cast<int>(2 * v.size()));
    return;
  }
  bool printable = true;
  for (const auto b : v) printable = printable && b >= 0x20 && b < 0x7F;
  if (printable) {
    s.push_back('"');
    for (const auto b : v) s.push_back(static_cast<char>(b));
    s.push_back('"');
    return;
  }
  s.push_back('[');
  s.append(hex(v));
  s.push_back(']');
}

std::string other(const FrameView& f) {
  std::string s = "command 0x";
  append_hex(s, f.command, 2);
  s.append(" (").append(std::to_string(f.data.size())).append(" data bytes)");
  return s;
}

std::string to_drive(const FrameView& f) {
  const auto d = f.data;
  std::string s;
  switch (f.command) {
    case command::reset_node:
      s = "reset node";
      if (!d.empty()) s.append(" (").append(std::to_string(d.size())).append(" data bytes ignored)");
      return s;
    case command::sdo_read:
      if (d.size() != 3) break;
      s = "SDO read ";
      address(s, d);
      return s;
    case command::sdo_write:
      if (d.size() < 3) break;
      s = "SDO write ";
      address(s, d);
      if (d.size() == 3) {
        s.append(" (no value)");
      } else {
        s.append(" = ");
        value(s, d.subspan(3));
      }
      return s;
    case command::sdo_abort:
      if (d.size() != 7) break;
      s = "abort request ";
      address(s, d);
      s.append(" 0x");
      append_hex(s, le32(d, 3), 8);
      return s;
    case command::controlword:
      if (d.size() != 2) break;
      s = "controlword 0x";
      append_hex(s, le16(d, 0), 4);
      return s;
    default: break;
  }
  return other(f);
}

std::string to_host(const FrameView& f) {
  const auto d = f.data;
  std::string s;
  switch (f.command) {
    case command::boot:
      s = "boot \"";
      for (const auto b : d) s.push_back(static_cast<char>(b));
      s.push_back('"');
      return s;
    case command::sdo_read:
      if (d.size() <= 3) break;
      s = "SDO read ";
      address(s, d);
      s.append(" → ");
      value(s, d.subspan(3));
      return s;
    case command::sdo_write:
      if (d.size() != 3) break;
      s = "SDO write ";
      address(s, d);
      s.append(" ok");
      return s;
    case command::sdo_error:
      if (d.size() == 7) {
        s = "error ";
        address(s, d);
        s.append(" 0x");
        append_hex(s, le32(d, 3), 8);
        return s;
      }
      if (d.size() != 3) break;
      s = "abort ";
      address(s, d);
      s.append(" acknowledged");
      return s;
    case command::controlword:
      if (d.size() != 1) break;
      if (d[0] == 0) return "controlword ok";
      s = "controlword refused (error ";
      s.append(std::to_string(d[0])).push_back(')');
      return s;
    case command::statusword:
      if (d.size() != 2) break;
      s = "statusword 0x";
      append_hex(s, le16(d, 0), 4);
      return s;
    case command::emcy:
      if (d.size() != 8) break;
      s = "EMCY ";
      append_hex(s, le16(d, 0), 4);
      s.append("h reg ");
      append_hex(s, d[2], 2);
      s.append(" word ");
      append_hex(s, le16(d, 3), 4);
      return s;
    default: break;
  }
  return other(f);
}

}  // namespace

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string s;
  s.reserve(bytes.size() * 3);
  for (const auto b : bytes) {
    if (!s.empty()) s.push_back(' ');
    append_hex(s, b, 2);
  }
  return s;
}

std::string describe(const FrameView& f, Direction dir) {
  return dir == Direction::to_drive ? to_drive(f) : to_host(f);
}

}  // namespace mcemu::faulhaber
