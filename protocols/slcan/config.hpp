// Settings of the SLCAN port (slcan-canopen.md §11.1, config section "slcan"). Plain values; the
// server fills them from --config (from_json) and the command line.
#pragma once

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>

namespace mcemu::slcan {

// The reply to a valid frame line (§3.5).
enum class FrameAck : std::uint8_t { z, cr, none };

struct SlcanConfig {
  FrameAck frame_ack = FrameAck::z;
  std::string version = "1010";                // exactly 4 decimal digits: `V1010\r`, `v1010\r`
  int serial_digits = 4;                       // 4 or 8 hex digits of 3404h.04 in the `N` reply
  std::optional<int> max_clients;              // unset: --max-clients (default 8) applies
  std::size_t queue_limit_bytes = 256 * 1024;  // per-session output cap (§3.1), applied by the TCP adapter
};

// Reads the "slcan" object of the config file. Absent keys keep their defaults. Throws
// std::invalid_argument with one line naming the key ("slcan.frame_ack: …") for an unknown key or
// a bad value.
SlcanConfig slcan_config_from_json(const nlohmann::json& section);

}  // namespace mcemu::slcan
