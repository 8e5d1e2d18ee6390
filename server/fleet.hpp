// The drives of one process (spec README "--drives", "--port-step", "--fleet"; issue 13): turns the
// process settings into one Settings per drive. Pure: no I/O (the fleet file is read by
// parse_command_line into Settings::fleet).
//
// --drives N: drive k (1…N) binds --bind + (k−1) and reports --ip + (k−1), both counted as 32-bit
//   numbers (127.0.0.255 + 1 = 127.0.1.0); with --port-step S the bind address stays and every
//   non-zero port is offset by (k−1)·S instead (port 0 stays 0: any free port). The reported
//   address is --ip + (k−1) in both forms, so every drive keeps its own identity.
// --fleet FILE: a JSON list; entry k starts from the process settings (command line + --config),
//   takes the same defaults as drive k of --drives, then its own keys: any option of --config
//   except the process-wide ones (config, fleet, drives, port-step, log-level), and any config
//   section ("objects", "plant", "slcan", …), which replaces the section of the same name.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "server/settings.hpp"

namespace mcemu::server {

// One Settings per drive, in drive order (drive k = element k−1). Throws UsageError naming the
// drive and the key (an address past 255.255.255.255, a port past 65535, an IPv6 or wildcard bind
// that cannot be counted without --port-step, a bad fleet entry).
std::vector<Settings> expand_fleet(const Settings& process);

// The Settings of the drive whose dictionary --dump-od/--dump-eds print: drive K of --drive K, or
// the one drive of the process. Throws UsageError when K is past the last drive, or when the
// process has more than one drive and no --drive names one (their dictionaries differ: model,
// config sections, the counted factory address 5007h).
Settings dump_target(const Settings& process);

// "127.0.0.255" + 1 → "127.0.1.0"; throws UsageError naming `what` on overflow.
std::string add_to_ipv4(const std::string& address, std::uint32_t offset, const std::string& what);

}  // namespace mcemu::server
