#include "server/fleet.hpp"

#include <set>

#include "drive/model/model_preset.hpp"

namespace mcemu::server {

using nlohmann::json;

namespace {

const std::set<std::string> k_process_keys = {"config", "fleet", "drives", "port-step", "log-level"};

std::string canonical(std::string key) {
  for (auto& ch : key) {
    if (ch == '_') ch = '-';
  }
  return key;
}

bool is_ipv4(const std::string& text) { return text.find(':') == std::string::npos; }

std::uint16_t step_port(std::uint16_t port, std::uint32_t offset, const std::string& what) {
  if (port == 0) return 0;
  const std::uint64_t p = std::uint64_t{port} + offset;
  if (p > 65535) {
    throw UsageError(what + " port " + std::to_string(port) + " + " + std::to_string(offset) +
                     " is past 65535 (choose a smaller --port-step or lower ports)");
  }
  return static_cast<std::uint16_t>(p);
}

// Without an explicit --ip the counted address is drive k's factory address (5007h in its factory
// image, persistence.md §6): a stored address still wins, as on drive 1.
void set_factory_ip(Settings& s) {
  const auto preset = model::find_preset(s.model);
  if (preset && preset->is_faulhaber()) return;  // no IP objects: the MC is reached over RS232
  const auto o = parse_ipv4(s.ip, "--ip");
  if (!s.config.is_object()) s.config = json::object();
  json& objects = s.config["objects"];
  if (!objects.is_object()) objects = json::object();
  for (int i = 0; i < 4; ++i) {
    const std::string key = "5007.0" + std::to_string(i + 1);
    if (!objects.contains(key)) objects[key] = o[static_cast<std::size_t>(i)];
  }
}

// Drive k of --drives N (also the starting point of fleet entry k).
Settings counted_drive(const Settings& process, std::size_t k) {
  Settings s = process;
  s.drives = 1;
  s.fleet = json::array();
  s.fleet_file.reset();
  const auto offset = static_cast<std::uint32_t>(k - 1);
  if (offset == 0) return s;
  const std::string what = "drive " + std::to_string(k);
  if (process.port_step) {
    const std::uint32_t by = offset * *process.port_step;
    s.refgo_port = step_port(process.refgo_port, by, what + ": --refgo-port");
    s.slcan_port = step_port(process.slcan_port, by, what + ": --slcan-port");
    s.http_port = step_port(process.http_port, by, what + ": --http-port");
    s.udp_port = step_port(process.udp_port, by, what + ": --udp-port");
    s.faulhaber_port = step_port(process.faulhaber_port, by, what + ": --faulhaber-port");
  } else {
    if (!is_ipv4(process.bind)) {
      throw UsageError("--drives with an IPv6 --bind needs --port-step (addresses are counted as IPv4 numbers)");
    }
    if (process.bind == "0.0.0.0") {
      throw UsageError("--drives with --bind 0.0.0.0 needs --port-step (the wildcard address cannot be counted)");
    }
    s.bind = add_to_ipv4(process.bind, offset, what + ": --bind");
  }
  s.ip = add_to_ipv4(process.ip, offset, what + ": --ip");
  // one pseudo-terminal per drive: drive k ≥ 2 gets PATH-k (docs/fleet.md)
  if (process.faulhaber_pty) s.faulhaber_pty = *process.faulhaber_pty + "-" + std::to_string(k);
  return s;
}

Settings fleet_entry(const Settings& process, std::size_t k, const json& entry) {
  const std::string what = "fleet entry " + std::to_string(k);
  if (!entry.is_object()) throw UsageError(what + " must be a JSON object");
  Settings s = counted_drive(process, k);
  json config = process.config.is_object() ? process.config : json::object();
  json flags = json::object();
  for (const auto& [key, value] : entry.items()) {
    if (k_process_keys.count(canonical(key))) {
      throw UsageError(what + ": \"" + key + "\" applies to the whole process, not to one drive");
    }
    if (value.is_object()) {
      config[key] = value;  // a config section replaces the process's section of that name
    } else {
      flags[key] = value;
    }
  }
  // The entry's own options win over everything (apply_config with no command-line flags given);
  // the sections of `config` are validated by their components when the unit is built.
  json merged = config;
  for (const auto& [key, value] : flags.items()) merged[key] = value;
  // Keep the process-wide scalar options out of the per-drive pass (they were applied already).
  for (auto it = merged.begin(); it != merged.end();) {
    if (!it.value().is_object() && !flags.contains(it.key())) {
      it = merged.erase(it);
    } else {
      ++it;
    }
  }
  try {
    apply_config(s, merged, {});
  } catch (const UsageError& e) {
    throw UsageError(what + ": " + e.what());
  }
  return s;
}

}  // namespace

std::string add_to_ipv4(const std::string& address, std::uint32_t offset, const std::string& what) {
  const auto o = parse_ipv4(address, what);
  const std::uint64_t n =
      (std::uint64_t{o[0]} << 24 | std::uint64_t{o[1]} << 16 | std::uint64_t{o[2]} << 8 | o[3]) + offset;
  if (n > 0xFFFFFFFFULL) {
    throw UsageError(what + " " + address + " + " + std::to_string(offset) + " is past 255.255.255.255");
  }
  return std::to_string((n >> 24) & 0xFF) + "." + std::to_string((n >> 16) & 0xFF) + "." +
         std::to_string((n >> 8) & 0xFF) + "." + std::to_string(n & 0xFF);
}

Settings dump_target(const Settings& process) {
  auto drives = expand_fleet(process);
  const std::string what = process.dump_eds ? "--dump-eds" : "--dump-od";
  if (process.dump_drive) {
    if (*process.dump_drive > drives.size()) {
      throw UsageError("--drive " + std::to_string(*process.dump_drive) + ": this process has " +
                       std::to_string(drives.size()) + (drives.size() == 1 ? " drive" : " drives"));
    }
    return drives[*process.dump_drive - 1];
  }
  if (drives.size() > 1) {
    throw UsageError(what + ": this process has " + std::to_string(drives.size()) +
                     " drives; choose the one to dump with --drive K (1 … " + std::to_string(drives.size()) + ")");
  }
  return drives.front();
}

std::vector<Settings> expand_fleet(const Settings& process) {
  std::vector<Settings> out;
  if (!process.fleet.empty()) {
    out.reserve(process.fleet.size());
    for (std::size_t k = 1; k <= process.fleet.size(); ++k) {
      out.push_back(fleet_entry(process, k, process.fleet[k - 1]));
    }
  } else {
    out.reserve(process.drives);
    for (std::size_t k = 1; k <= process.drives; ++k) out.push_back(counted_drive(process, k));
  }
  for (std::size_t k = 2; k <= out.size(); ++k) {
    if (!out[k - 1].ip_explicit) set_factory_ip(out[k - 1]);
  }
  return out;
}

}  // namespace mcemu::server
