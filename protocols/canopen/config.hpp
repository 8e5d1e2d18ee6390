// Settings of the CANopen node (slcan-canopen.md §11.1, config section "canopen"). Plain values;
// the node-id is not a setting (it is 3404h.03).
#pragma once

#include <chrono>
#include <nlohmann/json_fwd.hpp>

namespace mcemu::canopen {

struct CanopenConfig {
  std::chrono::milliseconds sdo_timeout{1000};                     // §6.8
  int sdo_block_size = 127;                                        // blksize announced for block downloads
  std::chrono::milliseconds bootup_delay_reset_node{50};           // §4.4
  std::chrono::milliseconds bootup_delay_reset_communication{10};  // also used at power on
  bool dynamic_pdo_mapping = false;                                // §9.7
};

// Reads the "canopen" object of the config file; absent keys keep their defaults. Throws
// std::invalid_argument with one line naming the key ("canopen.sdo_block_size: …").
CanopenConfig canopen_config_from_json(const nlohmann::json& section);

}  // namespace mcemu::canopen
