#include "protocols/faulhaber/describe.hpp"

namespace mcemu::faulhaber {

// Text is built by appending to one string: no temporaries per frame (the trace runs on every
// request), and no operator+ chains, for which GCC 12 reports a false -Wrestrict.
namespace {
constexpr char k_digits[] = "0123456789ABCDEF";
}  // namespace

// Both hex writers grow the string once and fill it in place: a push_back per character cost
// ~50 instructions per byte, a tenth of a whole SDO request (callgrind, bench/echo_ratio).
void append_hex(std::string& s, std::uint32_t v, int digits) {
  if (digits <= 0) return;
  const std::size_t at = s.size();
  s.resize(at + static_cast<std::size_t>(digits));
  char* p = s.data() + at;
  for (int i = digits - 1; i >= 0; --i) *p++ = k_digits[(v >> (4 * i)) & 0xF];
}

void append_hex(std::string& s, std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return;
  const std::size_t at = s.size();
  s.resize(at + 3 * bytes.size() - 1);  // "XX" per byte, one space between
  char* p = s.data() + at;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i > 0) *p++ = ' ';
    *p++ = k_digits[bytes[i] >> 4];
    *p++ = k_digits[bytes[i] & 0xF];
  }
}

namespace {

void append_count(std::string& s, std::size_t n) {
  char digits[24];
  int k = 0;
  do {
    digits[k++] = static_cast<char>('0' + n % 10);
    n /= 10;
  } while (n > 0);
  while (k > 0) s.push_back(digits[--k]);
}

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
  append_hex(s, v);
  s.push_back(']');
}

void other(std::string& s, const FrameView& f) {
  s.append("command 0x");
  append_hex(s, f.command, 2);
  s.append(" (");
  append_count(s, f.data.size());
  s.append(" data bytes)");
}

void to_drive(std::string& s, const FrameView& f) {
  const auto d = f.data;
  switch (f.command) {
    case command::reset_node:
      s.append("reset node");
      if (!d.empty()) {
        s.append(" (");
        append_count(s, d.size());
        s.append(" data bytes ignored)");
      }
      return;
    case command::sdo_read:
      if (d.size() != 3) break;
      s.append("SDO read ");
      address(s, d);
      return;
    case command::sdo_write:
      if (d.size() < 3) break;
      s.append("SDO write ");
      address(s, d);
      if (d.size() == 3) {
        s.append(" (no value)");
      } else {
        s.append(" = ");
        value(s, d.subspan(3));
      }
      return;
    case command::sdo_abort:
      if (d.size() != 7) break;
      s.append("abort request ");
      address(s, d);
      s.append(" 0x");
      append_hex(s, le32(d, 3), 8);
      return;
    case command::controlword:
      if (d.size() != 2) break;
      s.append("controlword 0x");
      append_hex(s, le16(d, 0), 4);
      return;
    default: break;
  }
  other(s, f);
}

void to_host(std::string& s, const FrameView& f) {
  const auto d = f.data;
  switch (f.command) {
    case command::boot:
      s.append("boot \"");
      for (const auto b : d) s.push_back(static_cast<char>(b));
      s.push_back('"');
      return;
    case command::sdo_read:
      if (d.size() <= 3) break;
      s.append("SDO read ");
      address(s, d);
      s.append(" → ");
      value(s, d.subspan(3));
      return;
    case command::sdo_write:
      if (d.size() != 3) break;
      s.append("SDO write ");
      address(s, d);
      s.append(" ok");
      return;
    case command::sdo_error:
      if (d.size() == 7) {
        s.append("error ");
        address(s, d);
        s.append(" 0x");
        append_hex(s, le32(d, 3), 8);
        return;
      }
      if (d.size() != 3) break;
      s.append("abort ");
      address(s, d);
      s.append(" acknowledged");
      return;
    case command::controlword:
      if (d.size() != 1) break;
      if (d[0] == 0) {
        s.append("controlword ok");
        return;
      }
      s.append("controlword refused (error ");
      append_count(s, d[0]);
      s.push_back(')');
      return;
    case command::statusword:
      if (d.size() != 2) break;
      s.append("statusword 0x");
      append_hex(s, le16(d, 0), 4);
      return;
    case command::emcy:
      if (d.size() != 8) break;
      s.append("EMCY ");
      append_hex(s, le16(d, 0), 4);
      s.append("h reg ");
      append_hex(s, d[2], 2);
      s.append(" word ");
      append_hex(s, le16(d, 3), 4);
      return;
    default: break;
  }
  other(s, f);
}

}  // namespace

void append_description(std::string& out, const FrameView& f, Direction dir) {
  if (dir == Direction::to_drive) {
    to_drive(out, f);
  } else {
    to_host(out, f);
  }
}

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string s;
  s.reserve(bytes.size() * 3);
  append_hex(s, bytes);
  return s;
}

std::string describe(const FrameView& f, Direction dir) {
  std::string s;
  append_description(s, f, dir);
  return s;
}

}  // namespace mcemu::faulhaber
