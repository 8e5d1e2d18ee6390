// Settings of the FAULHABER binary protocol (config section "faulhaber", faulhaber.md §4–§6).
// node_id and crc_check are factory values of dictionary entries (0x2400.03, 0x2400.04 bit 23),
// applied by whoever builds the FAULHABER dictionary; the rest configure the Port.
#pragma once

#include <cstdint>
#include <nlohmann/json_fwd.hpp>

#include "protocols/faulhaber/port.hpp"

namespace mcemu::faulhaber {

struct FaulhaberConfig {
  std::uint8_t node_id = k_default_node_id;  // faulhaber.node_id: factory value of 0x2400.03
  bool crc_check = true;                     // faulhaber.crc_check: factory 0x2400.04 bit 23 clear
  PortConfig port;                           // faulhaber.response_delay_ms, faulhaber.queue_limit_bytes
};

// Factory value of 0x2400.04: EMCY and asynchronous messages on (§6), bit 23 set when crc_check is off.
constexpr std::uint32_t factory_settings(const FaulhaberConfig& c) {
  return k_default_settings | (c.crc_check ? 0u : k_ignore_crc_bit);
}

// Reads the "faulhaber" object of the config file; absent keys keep their defaults. Throws
// std::invalid_argument with one line naming the key ("faulhaber.node_id: …"). The keys of the
// dictionary and of MC BASIC (device_name, serial, autostart, basic_statements_per_ms) are left to
// their own parsers; any other key is an error.
FaulhaberConfig faulhaber_config_from_json(const nlohmann::json& section);

}  // namespace mcemu::faulhaber
