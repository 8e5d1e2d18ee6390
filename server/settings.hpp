// The command line and --config file of mcemu (spec README "Command line"). Pure parsing: no I/O
// except reading the config file named on the command line.
//
// Precedence: command-line flag > config file > default. Every invalid flag or value is a
// UsageError with a one-line message; main prints it and exits with status 2.
#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "device/config_error.hpp"
#include "lint/config.hpp"
#include "sim/clock_mode.hpp"

namespace mcemu::server {

// An invalid flag or config value (one line; exit status 2). The bundle's config parsers throw the
// same type (device/config_error.hpp).
using UsageError = device::ConfigError;

struct Settings {
  std::string model = "MC349";
  std::string bind = "127.0.0.1";
  std::uint16_t refgo_port = 10001;
  std::uint16_t slcan_port = 15001;
  std::uint16_t http_port = 80;
  std::uint16_t udp_port = 14999;
  std::uint16_t faulhaber_port = 10002;      // FAULHABER binary protocol over TCP (faulhaber.md §2.1)
  std::optional<std::string> faulhaber_pty;  // a pseudo-terminal symlinked here (faulhaber.md §2.2)
  std::string ip = "192.168.2.150";
  bool ip_explicit = false;  // --ip on the command line or "ip" in the config (persistence.md §6)
  std::string state_dir = "./mcemu-state";
  std::optional<std::string> config_file;
  std::string log_level = "info";
  std::size_t refgo_max_clients = 8;
  std::size_t slcan_max_clients = 8;
  std::size_t http_max_clients = 32;
  std::size_t ws_max_clients = 16;  // "http": {"ws_max_clients": N} (web.md §10.5: 16 by default)
  std::size_t faulhaber_max_clients = 8;
  // Fleets (server/fleet.hpp): --drives N, --port-step S, --fleet FILE (its JSON list in `fleet`).
  std::size_t drives = 1;
  std::optional<std::uint32_t> port_step;
  std::optional<std::string> fleet_file;
  nlohmann::json fleet = nlohmann::json::array();
  // --idle-timeout: a TCP connection that sent nothing for this long is closed (0 = off); the line
  // servers (RefGo, SLCAN) and the HTTP server apply it.
  std::chrono::seconds idle_timeout{0};
  sim::ClockMode clock;  // --clock real | scaled:X | manual
  // --unsafe-scripts: where the script sandbox cannot be set up, run scripts without it (loudly).
  // Command line only: a config file cannot switch it on (docs/security.md).
  bool unsafe_scripts = false;
  // --api-token FILE (docs/security.md): the bearer token (the file's first line) that mcemu's own
  // emulator endpoints then require; "" = no token.
  std::optional<std::string> api_token_file;
  std::string api_token;
  // --lint off|warn|strict (docs/lint.md §3): the master lint's mode over the config's "lint.mode";
  // also "lint": "strict" in a config file or a fleet entry ("lint": {…} is the section).
  std::optional<lint::Mode> lint_mode;
  bool dump_od = false;
  bool dump_eds = false;
  // --drive K: the drive of --drives/--fleet whose dictionary --dump-od/--dump-eds print (1-based;
  // command line only, and only with a dump: server/fleet.hpp dump_target()).
  std::optional<std::size_t> dump_drive;
  bool help = false;
  bool version = false;
  // The config document (sections "objects", "model_overrides", "plant", "homing", "slcan",
  // "canopen", "settings", …) for the components that own them; {} without --config.
  nlohmann::json config = nlohmann::json::object();
};

// Parses argv (without argv[0]); reads and merges the --config file. Throws UsageError.
Settings parse_command_line(const std::vector<std::string>& args);
// Applies a config document (already parsed) below the given command-line flags; exposed for tests.
void apply_config(Settings& s, const nlohmann::json& config, const std::vector<std::string>& flags_given);

std::string help_text();

// The token of an --api-token file: its first line without surrounding white space; at least 16
// characters, no white space inside (throws UsageError naming the file otherwise).
std::string token_of_file_text(const std::string& text, const std::string& path);

// Dotted IPv4 → four octets (throws UsageError naming `what`).
std::array<std::uint8_t, 4> parse_ipv4(const std::string& text, const std::string& what);

}  // namespace mcemu::server
