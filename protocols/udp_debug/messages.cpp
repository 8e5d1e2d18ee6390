#include "protocols/udp_debug/messages.hpp"

namespace mcemu::udp_debug {

std::vector<std::string> upload_messages(std::string_view script_id) {
  return {"code: starting upload...\r\n", "code: upload complete, script id: " + std::string(script_id) + "\r\n"};
}

std::vector<std::string> startup_block(std::string_view ip, std::string_view script_id) {
  std::vector<std::string> out{
      "SYS_Initialize: The MPFS2 File System is mounted\r\n",
      "TCP/IP Stack: Initialization Ended - success \n\r",
      "Host MOVINGCAP TCP   - NBNS disabled\r\n",
      "IP Address: " + std::string(ip) + " \r\n",
      "REFGO - opening server\r\n",
  };
  for (auto& m : upload_messages(script_id)) out.push_back(std::move(m));
  return out;
}

std::string note(std::string_view text) { return "mcemu: " + std::string(text) + "\r\n"; }

}  // namespace mcemu::udp_debug
