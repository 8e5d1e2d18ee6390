// Everything the JSON API needs from outside the pure drive, in one struct the composition root
// fills (server/drive_web.cpp). Every member is optional: an absent hook gives the answer documented
// next to it (mostly 503 with error code "unavailable"), never a fake success.
//
// Threading: all hooks are called on the event-loop thread, from Router::handle().
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "drive/od/types.hpp"
#include "trace/trace.hpp"
#include "web/api/http_types.hpp"
#include "web/api/status.hpp"

namespace mcemu::web::api {

// What /api/v1/info reports (web.md §8.1) besides "scripting" and "clock".
struct Info {
  std::string version;
  std::string model;
  std::string display_name;
  std::string device_name;
  std::string software_version;
  std::uint32_t serial = 0;
  std::string ip;
  std::string mask;
  std::string bind;
  std::uint16_t refgo_port = 0;
  std::uint16_t slcan_port = 0;
  std::uint16_t http_port = 0;
  std::uint16_t udp_port = 0;
  std::uint16_t faulhaber_port = 0;
  std::string faulhaber_pty;  // the symlink of --faulhaber-pty ("" without)
  std::string state_dir;
};

// --clock (README): mode "real", "scaled" or "manual"; scale = drive time per wall time (0 manual).
struct ClockInfo {
  std::string mode = "real";
  double scale = 1;
};

// The UDP debug console as GET /api/v1/udp shows it (udp-debug.md §6); the server fills it.
struct UdpView {
  struct Listener {
    std::string address;
    std::uint16_t port = 0;
    std::uint64_t registered_ms = 0;  // drive time of the (latest) registration
    std::string registered_wall;      // UTC, "2026-01-15T10:15:02.123Z" ("" if unknown)
  };
  std::vector<Listener> listeners;
  std::size_t backlog_bytes = 0;
  std::size_t backlog_messages = 0;
  std::uint64_t datagrams_sent = 0;
  std::uint64_t datagrams_dropped = 0;  // refused by the kernel or by udp.drop
  std::uint64_t datagrams_received = 0;
  std::uint64_t ignored_payloads = 0;  // received datagrams that were not a registration
  std::vector<std::string> messages;   // the last (at most 500) console messages, oldest first
};

// The script engine as the API sees it (web.md §6, §8.7; scripting.md). Null in Services = no engine
// in this build: every script endpoint answers 503.
struct ScriptView {
  std::string id;     // 3500h.01, "(empty)" for the placeholder
  std::string state;  // OFF, RUN, BRK
  bool autostart = false;
  std::uint32_t length = 0;
  std::uint32_t crc32 = 0;
  int line = 0;
  std::string source;  // the visible part (cut at the first line starting with #private)
  bool has_private = false;
};
// The script sandbox as GET /api/v1/info and the Code page report it (docs/security.md).
struct SandboxView {
  bool known = false;   // false: the engine says nothing about a sandbox (no field in /api/v1/info)
  bool active = false;  // runs are sandboxed
  bool unsafe = false;  // runs without the sandbox because --unsafe-scripts allowed it
  std::string text;     // what the sandbox is (active), else the one sentence why there is none
};
class ScriptControl {
 public:
  virtual ~ScriptControl() = default;
  // scripting.md §10.1.8: false when no usable python3 was found; everything else still works and
  // a start sends the "engine unavailable" UDP line.
  virtual bool available() const = 0;
  virtual std::string engine() const = 0;  // "python3 3.11.2"; the reason while unavailable
  virtual SandboxView sandbox() const { return {}; }
  virtual ScriptView view() const = 0;
  // Replaces the script in RAM (web.md §6.1 effects); an error message → 400. The router has
  // checked 1 … 65 536 bytes.
  virtual std::optional<std::string> upload(std::string source) = 0;
  virtual void start() = 0;   // codeAct 3
  virtual void stop() = 0;    // codeAct 4
  virtual void pause() = 0;   // codeAct 1
  virtual void resume() = 0;  // codeAct 2
  // GET /program.html?codeAct=N (web.md §6.2): 1–6; other numbers do nothing.
  virtual void code_act(int n) = 0;
  virtual void kill() = 0;  // fault kind script.kill (udp-debug.md §4.6); only while not OFF
  // The status snapshot's python/refgo parts.
  virtual PythonStatus status() const = 0;
  virtual int refgo_attach_mode() const = 0;
};

struct Services {
  std::function<Info()> info;  // required by /api/v1/info (absent: empty strings)
  // Factory value of an entry (the persistence factory image); absent: the preset's value.
  std::function<std::optional<od::Value>(std::uint16_t, std::uint8_t)> factory;
  // --clock; absent: real, scale 1.
  std::function<ClockInfo()> clock;
  // --clock manual: run `ms` steps of 1 ms (in slices, web.md §8.10), then call done(drive time).
  // Called only in mode manual; absent there → 503.
  std::function<void(std::uint64_t ms, std::function<void(std::uint64_t time_ms)> done)> advance_clock;
  // POST /api/v1/power-cycle: persistence.md §7; call done() when the drive is powered up again.
  // Absent → 503.
  std::function<void(std::function<void()> done)> power_cycle;
  // GET /api/v1/udp; absent → 503. udp_listeners: the status snapshot's count (absent: 0).
  std::function<UdpView()> udp;
  std::function<int()> udp_listeners;
  // Emits "mcemu: <text>\r\n" on UDP (udp-debug.md §4.7); the router calls it only while the
  // setting udpEmulatorNotes is on.
  std::function<void(const std::string& text)> note;
  // Number of connected RefGo clients (status snapshot; absent: 0).
  std::function<int()> refgo_clients;
  // LED state for the status snapshot (absent: both off) and GET /api/v1/led (morse-led.md §6.2;
  // absent → 503).
  std::function<LedStatus()> led_state;
  // GET /api/v1/led with the query string after '?' ("" without one): the whole answer (200 or 400).
  std::function<Response(std::string_view query)> led;
  // GET /api/v1/eds: the EDS text as `mcemu --dump-eds` prints it; absent → 503.
  std::function<std::string()> eds;
  // Every request outside /api/ (pages, static assets, /program.html): returns true if it
  // answered (now or later through respond); false → the 404 page.
  std::function<bool(const Request&, const Respond&)> pages;
  // The trace ring (web.md §8.6); null = tracing off and 503 for the trace endpoints.
  trace::Ring* trace = nullptr;
  // The script engine; null = no engine in this build (503).
  ScriptControl* script = nullptr;
  // --api-token FILE (docs/security.md): when not empty, the route table's token rows (settings,
  // clock, power cycle, faults) answer 401 without "Authorization: Bearer <this>".
  std::string api_token;
};

}  // namespace mcemu::web::api
