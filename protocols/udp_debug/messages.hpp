// The exact bytes of the console messages mcemu itself produces (udp-debug.md §4.1, §4.2, §4.7).
// Pure formatting. Note the line endings: start-up line 2 ends "\n\r", the others "\r\n".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::udp_debug {

// The start-up block of every power-up (§4.1): seven messages, `ip` = the drive's own address
// (5007h, dotted decimal), `script_id` = the stored script's id ("(empty)" for the placeholder).
std::vector<std::string> startup_block(std::string_view ip, std::string_view script_id);

// "code: starting upload...\r\n" and "code: upload complete, script id: <id>\r\n" (§4.2).
std::vector<std::string> upload_messages(std::string_view script_id);

// An emulator note (§4.7): "mcemu: <text>\r\n".
std::string note(std::string_view text);
// The text of a fault note: "fault 7121h ERROR_STROKE" (the fault catalogue's names, drive/faults.hpp).
std::string fault_text(std::uint16_t emcy_code);

}  // namespace mcemu::udp_debug
