#include "server/settings.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "drive/model/model_preset.hpp"

namespace mcemu::server {

using nlohmann::json;

namespace {

constexpr std::uint64_t k_max_drives = 4096;

constexpr std::uint64_t k_max_idle_timeout_s = 7 * 24 * 3600;  // a week
const std::set<std::string> k_levels = {"trace", "debug", "info", "warn", "error", "critical", "off"};
// Top-level config sections owned by components; validated there.
const std::set<std::string> k_sections = {"objects",   "model_overrides", "plant", "homing", "slcan",
                                          "canopen",   "settings",        "refgo", "http",   "udp",
                                          "scripting", "faulhaber",       "trace"};

std::string names_of_presets() {
  std::string out;
  for (auto n : model::all_preset_names()) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

std::uint64_t parse_uint(const std::string& text, std::uint64_t max, const std::string& what) {
  std::uint64_t v = 0;
  const auto* end = text.data() + text.size();
  auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc{} || p != end || v > max) {
    throw UsageError("invalid value '" + text + "' for " + what + " (expected an integer 0…" + std::to_string(max) +
                     ")");
  }
  return v;
}

std::uint16_t parse_port(const std::string& text, const std::string& what) {
  return static_cast<std::uint16_t>(parse_uint(text, 65535, what));
}

std::size_t parse_clients(const std::string& text, const std::string& what) {
  const auto v = parse_uint(text, 100000, what);
  if (v == 0) throw UsageError("invalid value '0' for " + what + " (at least 1)");
  return static_cast<std::size_t>(v);
}

void check_bind(const std::string& text) {
  // IPv4 dotted quad or an IPv6 literal; name resolution is not done at start-up.
  if (text.find(':') != std::string::npos) {
    if (text.find_first_not_of("0123456789abcdefABCDEF:.") != std::string::npos) {
      throw UsageError("invalid value '" + text + "' for --bind (expected an IP address)");
    }
    return;
  }
  parse_ipv4(text, "--bind");
}

// Sets one option from its text; `what` names the flag in messages.
void set_option(Settings& s, const std::string& name, const std::string& value, const std::string& what) {
  if (name == "model") {
    if (!model::find_preset(value)) {
      throw UsageError("unknown model '" + value + "' for " + what + " (valid: " + names_of_presets() + ")");
    }
    s.model = value;
  } else if (name == "bind") {
    check_bind(value);
    s.bind = value;
  } else if (name == "refgo-port") {
    s.refgo_port = parse_port(value, what);
  } else if (name == "slcan-port") {
    s.slcan_port = parse_port(value, what);
  } else if (name == "http-port") {
    s.http_port = parse_port(value, what);
  } else if (name == "udp-port") {
    s.udp_port = parse_port(value, what);
  } else if (name == "faulhaber-port") {
    s.faulhaber_port = parse_port(value, what);
  } else if (name == "faulhaber-pty") {
    if (value.empty() || value.back() == '/')
      throw UsageError("invalid value '" + value + "' for " + what + " (a file path)");
    s.faulhaber_pty = value;
  } else if (name == "ip") {
    parse_ipv4(value, what);
    s.ip = value;
    s.ip_explicit = true;
  } else if (name == "state-dir") {
    if (value.empty()) throw UsageError("empty value for " + what);
    s.state_dir = value;
  } else if (name == "config") {
    s.config_file = value;
  } else if (name == "log-level") {
    if (!k_levels.count(value)) {
      throw UsageError("invalid value '" + value + "' for " + what +
                       " (trace, debug, info, warn, error, critical, off)");
    }
    s.log_level = value;
  } else if (name == "drives") {
    const auto n = parse_uint(value, k_max_drives, what);
    if (n == 0) throw UsageError("invalid value '0' for " + what + " (at least 1)");
    s.drives = static_cast<std::size_t>(n);
  } else if (name == "port-step") {
    const auto n = parse_uint(value, 65535, what);
    if (n == 0) throw UsageError("invalid value '0' for " + what + " (at least 1)");
    s.port_step = static_cast<std::uint32_t>(n);
  } else if (name == "fleet") {
    if (value.empty()) throw UsageError("empty value for " + what);
    s.fleet_file = value;
  } else if (name == "idle-timeout") {
    s.idle_timeout = std::chrono::seconds(parse_uint(value, k_max_idle_timeout_s, what));
  } else if (name == "max-clients") {
    const auto n = parse_clients(value, what);
    s.refgo_max_clients = s.slcan_max_clients = s.http_max_clients = s.faulhaber_max_clients = n;
  } else if (name == "api-token") {
    if (value.empty()) throw UsageError("empty value for " + what);
    s.api_token_file = value;
  } else if (name == "lint") {
    const auto mode = lint::mode_from_string(value);
    if (!mode) throw UsageError("invalid value '" + value + "' for " + what + " (off, warn, strict)");
    s.lint_mode = *mode;
  } else if (name == "clock") {
    try {
      s.clock = sim::parse_clock_mode(value);
    } catch (const std::invalid_argument& e) {
      throw UsageError("invalid value '" + value + "' for " + what + " (" + e.what() + ")");
    }
  } else {
    throw UsageError("unknown option --" + name + " (see --help)");
  }
}

const std::set<std::string> k_value_flags = {
    "model",     "bind",   "refgo-port",     "slcan-port",    "http-port",    "udp-port", "ip",
    "state-dir", "config", "log-level",      "max-clients",   "idle-timeout", "drives",   "port-step",
    "fleet",     "clock",  "faulhaber-port", "faulhaber-pty", "api-token",    "lint"};

std::string scalar_text(const json& v, const std::string& what) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_unsigned() || v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
  throw UsageError("invalid value " + v.dump() + " for " + what);
}

std::string invalid_ipv4(const std::string& text, const std::string& what) {
  std::string m = "invalid value '";
  m += text;
  m += "' for ";
  m += what;
  m += " (expected A.B.C.D)";
  return m;
}

json read_json_file(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw UsageError("cannot read " + what + " " + path);
  std::stringstream buf;
  buf << in.rdbuf();
  json doc = json::parse(buf.str(), nullptr, false);
  if (doc.is_discarded()) throw UsageError(what + " " + path + " is not valid JSON");
  return doc;
}

}  // namespace

std::string token_of_file_text(const std::string& text, const std::string& path) {
  std::string line = text.substr(0, text.find('\n'));
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; };
  while (!line.empty() && space(line.back())) line.pop_back();
  std::size_t first = 0;
  while (first < line.size() && space(line[first])) ++first;
  line.erase(0, first);
  if (line.size() < 16) {
    throw UsageError("the --api-token file " + path + " must hold a token of at least 16 characters on its first line");
  }
  if (std::any_of(line.begin(), line.end(), [&](char c) { return space(c) || static_cast<unsigned char>(c) < 0x20; })) {
    throw UsageError("the --api-token file " + path + ": the token must not contain white space or control characters");
  }
  return line;
}

std::array<std::uint8_t, 4> parse_ipv4(const std::string& text, const std::string& what) {
  std::array<std::uint8_t, 4> out{};
  std::size_t pos = 0;
  for (int i = 0; i < 4; ++i) {
    const std::size_t dot = i < 3 ? text.find('.', pos) : text.size();
    if (dot == std::string::npos) throw UsageError(invalid_ipv4(text, what));
    const std::string part = text.substr(pos, dot - pos);
    std::uint64_t v = 0;
    auto [p, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
    if (part.empty() || part.size() > 3 || ec != std::errc{} || p != part.data() + part.size() || v > 255) {
      throw UsageError(invalid_ipv4(text, what));
    }
    out[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v);
    pos = dot + 1;
  }
  return out;
}

void apply_config(Settings& s, const json& config, const std::vector<std::string>& flags_given) {
  if (!config.is_object()) throw UsageError("config: the document must be a JSON object");
  const auto given = [&](const std::string& n) {
    return std::find(flags_given.begin(), flags_given.end(), n) != flags_given.end();
  };
  for (const auto& [key, value] : config.items()) {
    std::string name = key;
    std::replace(name.begin(), name.end(), '_', '-');
    if (key == "lint" && value.is_object()) continue;  // the section (docs/lint.md §3); a string is --lint
    if (k_sections.count(key)) {
      if (!value.is_object()) throw UsageError("config: \"" + key + "\" must be an object");
      continue;
    }
    if (name == "config" || !k_value_flags.count(name)) throw UsageError("config: unknown key \"" + key + "\"");
    if (given(name)) continue;  // the command line wins
    set_option(s, name, scalar_text(value, "config key \"" + key + "\""), "config key \"" + key + "\"");
  }
  // per-service connection limits (README: a per-service key overrides --max-clients)
  for (const auto& [section, target] : {std::pair<const char*, std::size_t*>{"refgo", &s.refgo_max_clients},
                                        {"slcan", &s.slcan_max_clients},
                                        {"http", &s.http_max_clients},
                                        {"faulhaber", &s.faulhaber_max_clients}}) {
    if (config.contains(section) && config[section].contains("max_clients")) {
      const std::string what = std::string("config key \"") + section + ".max_clients\"";
      *target = parse_clients(scalar_text(config[section]["max_clients"], what), what);
    }
  }
  // WebSockets of the HTTP port (a dashboard with many viewers); each is also one of http.max_clients
  if (config.contains("http") && config["http"].contains("ws_max_clients")) {
    const std::string what = "config key \"http.ws_max_clients\"";
    s.ws_max_clients = parse_clients(scalar_text(config["http"]["ws_max_clients"], what), what);
  }
  s.config = config;
}

Settings parse_command_line(const std::vector<std::string>& args) {
  Settings s;
  std::vector<std::string> given;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0) throw UsageError("unexpected argument '" + a + "' (see --help)");
    std::string name = a.substr(2);
    std::optional<std::string> value;
    if (auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (name == "help" || name == "version" || name == "dump-od" || name == "dump-eds" || name == "unsafe-scripts") {
      if (value) throw UsageError("option --" + name + " takes no value");
      (name == "help"             ? s.help
       : name == "version"        ? s.version
       : name == "dump-od"        ? s.dump_od
       : name == "unsafe-scripts" ? s.unsafe_scripts
                                  : s.dump_eds) = true;
      continue;
    }
    if (name == "drive") {  // not a config key: it only selects what a dump prints
      if (!value) {
        if (i + 1 >= args.size()) throw UsageError("option --drive needs a value");
        value = args[++i];
      }
      const auto k = parse_uint(*value, k_max_drives, "--drive");
      if (k == 0) throw UsageError("invalid value '0' for --drive (drives are counted from 1)");
      s.dump_drive = static_cast<std::size_t>(k);
      continue;
    }
    if (!k_value_flags.count(name)) throw UsageError("unknown option --" + name + " (see --help)");
    if (!value) {
      if (i + 1 >= args.size()) throw UsageError("option --" + name + " needs a value");
      value = args[++i];
    }
    set_option(s, name, *value, "--" + name);
    given.push_back(name);
  }
  if (s.help || s.version) return s;
  if (s.dump_drive && !s.dump_od && !s.dump_eds) {
    throw UsageError("--drive K selects the drive whose dictionary --dump-od or --dump-eds prints");
  }
  if (s.config_file) {
    // Re-apply command-line values after the config so that they win.
    apply_config(s, read_json_file(*s.config_file, "config file"), given);
  }
  if (s.api_token_file) {
    std::ifstream in(*s.api_token_file);
    if (!in) throw UsageError("cannot read the --api-token file " + *s.api_token_file);
    std::stringstream buf;
    buf << in.rdbuf();
    s.api_token = token_of_file_text(buf.str(), *s.api_token_file);
  }
  if (s.fleet_file) {
    s.fleet = read_json_file(*s.fleet_file, "fleet file");
    if (!s.fleet.is_array() || s.fleet.empty()) {
      throw UsageError("fleet file " + *s.fleet_file + " must be a non-empty JSON list of drives");
    }
    if (s.drives != 1) throw UsageError("--drives and --fleet cannot be combined (the fleet file lists the drives)");
  }
  return s;
}

std::string help_text() {
  return R"(mcemu — emulator of a Fullmo MovingCap Ethernet servo drive and of the FAULHABER
MotionController V3.0

Usage: mcemu [options]

  --model NAME        drive model preset (default MC349): MC349, MC349_AE, MCN23, MCFLAT,
                      MCSHORT, MC632, MC634, MC636, PUSHTRACK; FAULHABER: FH_MC5004, FH_MC5005,
                      FH_MC5010, FH_MCS (binary protocol + JSON API, docs/faulhaber.md)
  --bind ADDR         address all services listen on (default 127.0.0.1)
  --refgo-port N      RefGo text commands, TCP (default 10001; 0 = any free port, logged)
  --slcan-port N      CANopen over SLCAN, TCP (default 15001)
  --http-port N       web UI and JSON API, HTTP (default 80)
  --udp-port N        debug output, UDP (default 14999)
  --faulhaber-port N  FAULHABER binary RS232 protocol over TCP (default 10002; FH_ models only)
  --faulhaber-pty P   also a pseudo-terminal, its subordinate side symlinked at P (a serial port
                      for pyserial, minicom …; removed at exit; FH_ models only)
  --ip A.B.C.D        the drive's own IP address as it reports it (default 192.168.2.150)
  --state-dir DIR     where Store Permanently keeps parameters (default ./mcemu-state)
  --config FILE       JSON file with any of these options (without "--") and sections
                      "objects", "model_overrides", "plant", "homing", "slcan", "canopen", "settings",
                      "trace" ({"events": N}: the trace ring's size, default 10000)
  --log-level L       trace, debug, info, warn, error, critical, off (default info)
  --max-clients N     simultaneous TCP connections per service (default 8 RefGo/SLCAN/FAULHABER,
                      32 HTTP)
  --drives N          N independent drives in this process (default 1): drive k listens on
                      --bind + (k-1) and reports --ip + (k-1), state file drive-k.json
  --port-step S       with --drives: one bind address, drive k's ports are each port + (k-1)*S
  --fleet FILE        JSON list of drives, each with its own model, bind, ip, ports and config
                      sections (docs/fleet.md)
  --idle-timeout S    close a TCP connection that sent nothing for S seconds (default 0 = off;
                      TCP keepalive is always on)
  --clock MODE        real (default: 1 ms steps paced by the wall clock), scaled:X (drive time =
                      X x wall time, 0.1 <= X <= 1000) or manual (POST /api/v1/clock/advance)
  --api-token FILE    mcemu's own emulator endpoints (settings, clock, power cycle, faults) then
                      need "Authorization: Bearer <the file's first line>"; the drive's own pages
                      and endpoints stay open as on the real drive (docs/security.md)
  --lint MODE         the master lint (docs/lint.md): off, warn (default: findings on the trace
                      channel lint and GET /api/v1/lint) or strict (warn-level findings fail
                      test-kit tests too)
  --unsafe-scripts    run MovingCap CODE scripts even where their sandbox (bwrap, seccomp) cannot
                      be set up: they then run with mcemu's user rights and network access
                      (command line only; docs/security.md)
  --dump-od           print the object dictionary of the model as JSON and exit
  --dump-eds          print the model's CANopen EDS (CiA 306) and exit, e.g. for python-canopen
  --drive K           with --dump-od/--dump-eds and --drives/--fleet: dump drive K (its model and
                      config); a process of more than one drive needs it
  --version           print the version and exit
  --help              print this text and exit
)";
}

}  // namespace mcemu::server
