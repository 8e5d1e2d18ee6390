// The message codec between mcemu's loop and the script engine process (scripting.md §10.2): one
// socketpair, length-prefixed messages. The runner (scripting/runner/ipc.py) implements the same
// layout; tests/scripting/ipc_test.cpp pins it.
//
//   frame   := u32 LE payload length, payload           (payload length 1 … k_max_payload)
//   payload := u8 kind, body
//   values  := u16 LE count, count × value (at most 65535)
//   value   := 'N' | 'I' i64 LE | 'B' u32 LE length, bytes | 'S' u32 LE length, UTF-8 bytes
//
// Kinds, runner → loop:  'H' hello (body: engine version text), 'K' compiled (values: ok, line),
//   'C' call (u16 LE function id, values), 'O' output (raw bytes), 'Z' sleep (values: duration µs),
//   'X' cancel the running sleep, 'E' end (values: how, line), 'F' fatal runner error (text), 'L' a log line (text),
//   'N' open a socket for mcnet (values: kind, host, port — NetRequest).
// Kinds, loop → runner:  'S' start (values, see engine), 'R' reply (values), 'W' wake. The reply to
//   'N' is 'R' (values: errno, peer address) with the socket attached as SCM_RIGHTS when errno is 0
//   or EINPROGRESS (the sandboxed runner cannot make sockets itself).
//
// Pure: no I/O; decoding never throws and never reads past the input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::scripting::ipc {

inline constexpr std::size_t k_header = 4;
inline constexpr std::size_t k_max_payload = 1U << 20;  // a larger length is a protocol error

enum class Kind : char {
  hello = 'H',
  compiled = 'K',
  call = 'C',
  output = 'O',
  sleep = 'Z',
  cancel = 'X',
  end = 'E',
  fatal = 'F',
  log = 'L',
  net = 'N',
  start = 'S',
  reply = 'R',
  wake = 'W',
};

// How a run ended ('E' message).
enum class EndHow : std::int64_t { finished = 0, system_exit = 1, exception = 2 };

struct Value {
  enum class Tag : char { none = 'N', integer = 'I', bytes = 'B', text = 'S' };
  Tag tag = Tag::none;
  std::int64_t i = 0;
  std::string s;

  static Value none() { return {}; }
  static Value integer(std::int64_t v) { return {Tag::integer, v, {}}; }
  static Value bytes(std::string b) { return {Tag::bytes, 0, std::move(b)}; }
  static Value text(std::string t) { return {Tag::text, 0, std::move(t)}; }
  bool operator==(const Value&) const = default;
};

struct Message {
  Kind kind = Kind::hello;
  std::string body;
};

// One step of the decoder: how many bytes of `buffer` were consumed and the message, if complete.
struct Decoded {
  std::size_t consumed = 0;
  std::optional<Message> message;
  bool error = false;  // bad length: the stream cannot be resynchronised
};
Decoded decode(std::string_view buffer);

std::string encode(Kind kind, std::string_view body);

std::string encode_values(std::span<const Value> values);
std::optional<std::vector<Value>> decode_values(std::string_view body);

// 'C' body: function id + values.
struct Call {
  std::uint16_t function = 0;
  std::vector<Value> args;
};
std::string encode_call(const Call& call);
std::optional<Call> decode_call(std::string_view body);

// 'N' body: the socket an mcnet object needs (scripting.md §7.2). host: the peer of a client or of
// a UDP peer ("" otherwise); the local address is always the drive's --bind, never the script's.
struct NetRequest {
  enum class Kind : std::uint8_t { server, client, udp };
  Kind kind = Kind::server;
  std::string host;
  std::uint16_t port = 0;
  bool operator==(const NetRequest&) const = default;
};
std::string encode_net(const NetRequest& request);
// nullopt for anything but ("server" | "client" | "udp", text, 1 … 65535); a client needs a host.
std::optional<NetRequest> decode_net(std::string_view body);

}  // namespace mcemu::scripting::ipc
