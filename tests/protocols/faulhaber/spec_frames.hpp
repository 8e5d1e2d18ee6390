// The byte-exact example frames of faulhaber.md §5 (every row, node 1) and the reference frames of
// §3, as the spec prints them. Shared by the codec, dispatcher and port tests.
#pragma once

#include <array>
#include <string_view>

namespace mcemu::faulhaber::test {

struct SpecFrame {
  const char* name;
  bool to_drive;  // H→D
  std::string_view hex;
};

inline constexpr std::array<SpecFrame, 36> k_spec_frames = {{
    // §5 table
    {"read 6041h.00", true, "53 07 01 01 41 60 00 73 45"},
    {"6041h = 0x0040", false, "53 09 01 01 41 60 00 40 00 C2 45"},
    {"6041h = 0x0427", false, "53 09 01 01 41 60 00 27 04 F4 45"},
    {"write 6040h.00 = 0x0006", true, "53 09 01 02 40 60 00 06 00 2C 45"},
    {"write response 6040h.00", false, "53 07 01 02 40 60 00 DB 45"},
    {"write 6040h.00 = 0x000F", true, "53 09 01 02 40 60 00 0F 00 25 45"},
    {"write 6060h.00 = 3", true, "53 08 01 02 60 60 00 03 A2 45"},
    {"write response 6060h.00", false, "53 07 01 02 60 60 00 FB 45"},
    {"write 60FFh.00 = 100", true, "53 0B 01 02 FF 60 00 64 00 00 00 59 45"},
    {"read 3005h.09", true, "53 07 01 01 05 30 09 3B 45"},
    {"3005h.09 = -1", false, "53 0B 01 01 05 30 09 FF FF FF FF 9D 45"},
    {"read 1234h.00", true, "53 07 01 01 34 12 00 8B 45"},
    {"error 1234h.00 0x06020000", false, "53 0B 01 03 34 12 00 00 00 02 06 2B 45"},
    {"write 6041h.00", true, "53 09 01 02 41 60 00 00 00 2B 45"},
    {"error 6041h.00 0x06010002", false, "53 0B 01 03 41 60 00 02 00 01 06 78 45"},
    {"statusword 0x0040", false, "53 06 01 05 40 00 17 45"},
    {"statusword 0x0021", false, "53 06 01 05 21 00 23 45"},
    {"statusword 0x0027", false, "53 06 01 05 27 00 8F 45"},
    {"statusword 0x0427", false, "53 06 01 05 27 04 21 45"},
    {"EMCY 3210h", false, "53 0C 01 07 10 32 05 04 00 00 00 00 83 45"},
    {"EMCY error reset", false, "53 0C 01 07 00 00 00 00 00 00 00 00 A0 45"},
    {"boot MC 5005", false, "53 0B 01 00 4D 43 20 35 30 30 35 8E 45"},
    {"boot MCS 3242 BX4 ET", false, "53 13 01 00 4D 43 53 20 33 32 34 32 20 42 58 34 20 45 54 A8 45"},
    {"reset node", true, "53 04 01 00 50 45"},
    {"controlword 0x0006", true, "53 06 01 04 06 00 50 45"},
    {"controlword 0x000F", true, "53 06 01 04 0F 00 59 45"},
    {"controlword response OK", false, "53 05 01 04 00 55 45"},
    {"write 2400h.04 = 0x00010000", true, "53 0B 01 02 00 24 04 00 00 01 00 29 45"},
    {"write response 2400h.04", false, "53 07 01 02 00 24 04 8E 45"},
    {"EMCY 8611h", false, "53 0C 01 07 11 86 21 02 00 00 00 00 14 45"},
    {"answer to abort 1234h.00", false, "53 07 01 03 34 12 00 DC 45"},
    // §3 third-party reference frames
    {"read 6064h", true, "53 07 01 01 64 60 00 56 45"},
    {"6064h = 9 (CRC 0x53)", false, "53 0B 01 01 64 60 00 09 00 00 00 53 45"},
    {"6041h = 0x0440", false, "53 09 01 01 41 60 00 40 04 6C 45"},
    // §3 RS232 capture (also in the §5 table)
    {"RS232 write request", true, "53 09 01 02 40 60 00 06 00 2C 45"},
    {"RS232 write response", false, "53 07 01 02 40 60 00 DB 45"},
}};

}  // namespace mcemu::faulhaber::test
